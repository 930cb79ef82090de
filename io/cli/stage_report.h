// --stats: the wavefront's time per stage, rays per second by ray type and
// paths alive per bounce.
#pragma once

#include "kernels/render_stats.h"
#include "wavefront/stage_stats.h"

namespace pt::cli {

void print_stage_stats(const wf::StageStats& stages, const RenderStats& totals);

}  // namespace pt::cli
