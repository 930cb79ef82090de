// The camera a command line asks for: the scene's (or the -c file's) at the
// output size, with -b / -d's thin lens.
#pragma once

#include "cli_options.h"
#include "kernels/scene/camera.h"
#include "kernels/scene/scene.h"

namespace pt::cli {

/// -b without -d (or a file's focal distance) focuses on the plane through
/// the scene's centre. Throws InputError for a camera file that does not read.
Camera render_camera(const Options& o, const Scene& scene);

}  // namespace pt::cli
