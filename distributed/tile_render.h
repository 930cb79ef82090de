// Rendering by tiles, as mpirun ranks and --shard jobs do: one tile at a time
// through the region renderer, with the render region narrowed to the tile.
#pragma once

#include <atomic>
#include <optional>

#include "io/tile_set.h"
#include "region_renderer.h"

namespace pt::dist {

struct RenderedTile {
  TilePixels pixels;
  RenderStats stats;  ///< seconds: the time this tile took
};

/// Renders tile `t` of `grid` with all of the settings' threads; nullopt if
/// `cancel` stopped it first.
std::optional<RenderedTile> render_tile(const RegionRenderer& render, const RenderSettings& rs, const TileGrid& grid,
                                        uint32_t t, const std::atomic<bool>* cancel);

}  // namespace pt::dist
