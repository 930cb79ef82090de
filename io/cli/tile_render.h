// Rendering by tiles, as mpirun ranks and --shard jobs do: one tile at a time
// through the chosen engine with the render region narrowed to the tile, and
// the header that names what a set of tiles belongs to.
#pragma once

#include <atomic>
#include <optional>

#include "cli_options.h"
#include "io/tile_set.h"
#include "kernels/camera.h"
#include "kernels/scene.h"
#include "render_engines.h"

namespace pt::cli {

struct RenderedTile {
  TilePixels pixels;
  RenderStats stats;  ///< seconds: the time this tile took
};

/// Renders tile `t` of `grid` with all of the settings' threads; nullopt if
/// `cancel` stopped it first.
std::optional<RenderedTile> render_tile(const EngineRunner& engine, const RenderSettings& rs, const TileGrid& grid,
                                        uint32_t t, const std::atomic<bool>* cancel);

/// What the tiles of this render are of (fingerprint of engine, BVH, scene,
/// camera, settings and tile size; image size; output encoding).
TileSetHeader tile_set_header(const Options& o, const Scene& scene, const Camera& camera);

}  // namespace pt::cli
