// What the tile runner renders with: any engine behind one function that
// renders the region of its settings (rs.region) and honours the control's
// cancel flag and crop_film. The command line passes its engine; tests pass
// functions that make known pixels.
#pragma once

#include <functional>

#include "kernels/render/render_job.h"

namespace pt::dist {

using RegionRenderer = std::function<RenderOutput(const RenderSettings&, const RenderControl&)>;

}  // namespace pt::dist
