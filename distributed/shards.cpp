// render_shard and merge_shards.
#include "shards.h"

#include <algorithm>
#include <map>
#include <sstream>

#include "io/scene_error.h"
#include "tile_render.h"

namespace pt::dist {

std::optional<TileSet> render_shard(const RegionRenderer& render, const RenderSettings& rs, const TileSetHeader& header,
                                    uint32_t index, uint32_t count, const std::atomic<bool>& cancel,
                                    const std::function<void(double)>& progress) {
  TileSet set;
  set.header = header;
  const TileGrid grid = header.grid();
  const uint32_t mine = grid.count() > index ? (grid.count() - index + count - 1) / count : 0;
  for (uint32_t t = index; t < grid.count(); t += count) {
    std::optional<RenderedTile> tile = render_tile(render, rs, grid, t, &cancel);
    if (!tile) return std::nullopt;
    set.stats.add_render(tile->stats);
    set.tiles.push_back(std::move(tile->pixels));
    if (progress) progress(double(set.tiles.size()) / std::max<uint32_t>(1, mine));
  }
  return set;
}

namespace {

/// The first field in which two headers differ, for the error message.
std::string first_difference(const TileSetHeader& a, const TileSetHeader& b) {
  if (a.width != b.width || a.height != b.height)
    return "image " + std::to_string(b.width) + "x" + std::to_string(b.height) + " against " + std::to_string(a.width) +
           "x" + std::to_string(a.height);
  if (a.tile_size != b.tile_size)
    return "tile size " + std::to_string(b.tile_size) + " against " + std::to_string(a.tile_size);
  if (a.fingerprint != b.fingerprint) {
    std::istringstream sa(a.fingerprint), sb(b.fingerprint);
    std::string ta, tb;
    while (sa >> ta && sb >> tb)
      if (ta != tb) return "its " + tb + " against " + ta;
    return "its render settings";
  }
  return "its output encoding";
}

}  // namespace

MergedImage merge_shards(const std::vector<NamedTileSet>& parts) {
  if (parts.empty()) throw InputError("--merge: no parts");
  std::map<uint32_t, size_t> owner;  // tile -> part
  for (size_t p = 0; p < parts.size(); ++p) {
    const TileSet& set = parts[p].set;
    if (!(set.header == parts.front().set.header))
      throw InputError(parts[p].name + ": a part of a different render than " + parts.front().name + " (" +
                       first_difference(parts.front().set.header, set.header) + ")");
    for (const TilePixels& t : set.tiles) {
      auto [it, fresh] = owner.emplace(t.tile, p);
      if (!fresh)
        throw InputError(parts[p].name + ": tile " + std::to_string(t.tile) + " is also in " + parts[it->second].name +
                         " (the same shard given twice?)");
    }
  }
  MergedImage merged;
  merged.header = parts.front().set.header;
  std::vector<const TilePixels*> tiles;
  for (const NamedTileSet& part : parts) {
    for (const TilePixels& t : part.set.tiles) tiles.push_back(&t);
    merged.stats.add_render(part.set.stats);
  }
  merged.tiles = tiles.size();
  try {
    merged.film = assemble_film(merged.header, tiles);
  } catch (const InputError& e) { throw InputError("--merge: " + std::string(e.what()) + "; give every shard's part"); }
  return merged;
}

}  // namespace pt::dist
