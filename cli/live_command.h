// pathtracer --serve [PORT]: loads the scene as a render would and hands it,
// with the command line's camera and settings, to the live view (live/).
#pragma once

#include <atomic>

#include "cli_options.h"

namespace pt::cli {

/// Serves until `stop`; the exit code. Throws InputError for a scene, camera
/// file or address that does not work.
int run_live_view(const Options& o, const std::atomic<bool>& stop);

}  // namespace pt::cli
