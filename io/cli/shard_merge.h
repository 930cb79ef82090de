// Rendering without mpirun, for batch schedulers whose job arrays cannot run
// it: --shard I/N renders the tiles t with t % N == I into a tile set, and
// --merge OUT PART... pastes every shard's tiles into the image one process
// would have rendered, bit for bit.
#pragma once

#include <atomic>
#include <filesystem>

#include "cli_options.h"
#include "kernels/camera.h"
#include "kernels/scene.h"
#include "render_engines.h"

namespace pt::cli {

/// Renders this shard's tiles and writes them to `output`. Returns false if
/// `cancel` stopped it (nothing is written then).
bool run_shard(const Options& o, const Scene& scene, const Camera& camera, const EngineRunner& engine,
               const std::filesystem::path& output, const std::atomic<bool>& cancel);

/// Assembles o.merge's parts into its output (throws InputError on parts of
/// different renders, a tile in two parts, or tiles that no part holds).
int run_merge(const Options& o);

}  // namespace pt::cli
