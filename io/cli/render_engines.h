// Dispatches a render to the engine and acceleration structure the options name.
#pragma once

#include "cli_options.h"
#include "kernels/render_job.h"

namespace pt::cli {

/// Throws InputError for combinations that do not exist.
RenderOutput render_with_engine(const Options& o, const Scene& scene, const Camera& camera,
                                const RenderControl& control);

}  // namespace pt::cli
