// Rendering without mpirun, for batch schedulers whose job arrays cannot run
// it: shard I of N renders the tiles t with t % N == I into a tile set, and
// the sets of every shard merge into the image one process would have
// rendered, bit for bit.
#pragma once

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "io/tile_set.h"
#include "region_renderer.h"

namespace pt::dist {

/// Renders shard `index` of `count` of the tiles `header` describes;
/// `progress(fraction)` after each tile. nullopt if `cancel` stopped it (a
/// shard is all or nothing).
std::optional<TileSet> render_shard(const RegionRenderer& render, const RenderSettings& rs, const TileSetHeader& header,
                                    uint32_t index, uint32_t count, const std::atomic<bool>& cancel,
                                    const std::function<void(double)>& progress = {});

/// A tile set and the name it is known by in messages (its file).
struct NamedTileSet {
  std::string name;
  TileSet set;
};

struct MergedImage {
  Film film;
  TileSetHeader header;
  RenderStats stats;  ///< summed over the parts
  size_t tiles = 0;
};

/// Pastes the parts' tiles into one film. Throws InputError naming the part
/// for parts of different renders (and the first setting that differs), a
/// tile in two parts, or tiles that no part holds.
MergedImage merge_shards(const std::vector<NamedTileSet>& parts);

}  // namespace pt::dist
