// The command line's tile jobs: --shard I/N renders this job's share of the
// tiles into a tile set file, --merge OUT PART... assembles every shard's file
// into the image (distributed/shards.h does the work), and the header that
// names what a set of tiles belongs to (for shards, mpirun and checkpoints).
#pragma once

#include <atomic>
#include <filesystem>

#include "cli_options.h"
#include "distributed/region_renderer.h"
#include "io/tile_set.h"
#include "kernels/scene/camera.h"
#include "kernels/scene/scene.h"
#include "render_engines.h"

namespace pt::cli {

/// What the tiles of this render are of (fingerprint of engine, BVH, scene,
/// camera, settings and tile size; image size; output encoding).
TileSetHeader tile_set_header(const Options& o, const Scene& scene, const Camera& camera);

/// The engine as the tile runner's region renderer.
dist::RegionRenderer region_renderer(const EngineRunner& engine);

/// Renders this shard's tiles and writes them to `output`. Returns false if
/// `cancel` stopped it (nothing is written then).
bool run_shard(const Options& o, const Scene& scene, const Camera& camera, const EngineRunner& engine,
               const std::filesystem::path& output, const std::atomic<bool>& cancel);

/// Assembles o.merge's parts into its output (throws InputError on parts of
/// different renders, a tile in two parts, or tiles that no part holds).
int run_merge(const Options& o);

}  // namespace pt::cli
