// run_shard and run_merge.
#include "shard_merge.h"

#include <cstdio>
#include <map>
#include <sstream>

#include "io/atomic_file.h"
#include "io/image_output.h"
#include "io/scene_error.h"
#include "progress_bar.h"
#include "render_outputs.h"
#include "tile_render.h"

namespace pt::cli {

bool run_shard(const Options& o, const Scene& scene, const Camera& camera, const EngineRunner& engine,
               const std::filesystem::path& output, const std::atomic<bool>& cancel) {
  TileSet set;
  set.header = tile_set_header(o, scene, camera);
  TileGrid grid = set.header.grid();
  const uint32_t n = uint32_t(o.shard_count), mine = grid.count() > uint32_t(o.shard_index)
                                                         ? (grid.count() - uint32_t(o.shard_index) + n - 1) / n
                                                         : 0;
  ProgressBar bar(!o.quiet);
  for (uint32_t t = uint32_t(o.shard_index); t < grid.count(); t += n) {
    std::optional<RenderedTile> tile = render_tile(engine, o.settings, grid, t, &cancel);
    if (!tile) {
      bar.finish();
      std::fprintf(stderr, "interrupted: shard %d/%d not written (a shard is written whole; run it again)\n",
                   o.shard_index, o.shard_count);
      return false;
    }
    set.stats.add_render(tile->stats);
    set.tiles.push_back(std::move(tile->pixels));
    bar.update(double(set.tiles.size()) / std::max<uint32_t>(1, mine));
  }
  bar.finish();
  save_tile_set(output, set);
  if (!o.quiet)
    std::printf("Shard %d/%d: %zu of %u tiles in %.3f s, %llu rays; wrote %s\n", o.shard_index, o.shard_count,
                set.tiles.size(), grid.count(), set.stats.seconds, static_cast<unsigned long long>(set.stats.rays()),
                output.c_str());
  return true;
}

namespace {

/// The first field in which two headers differ, for the error message.
std::string first_difference(const TileSetHeader& a, const TileSetHeader& b) {
  if (a.width != b.width || a.height != b.height)
    return "image " + std::to_string(b.width) + "x" + std::to_string(b.height) + " against " +
           std::to_string(a.width) + "x" + std::to_string(a.height);
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

int run_merge(const Options& o) {
  const std::filesystem::path output = o.merge.front();
  std::vector<TileSet> parts;
  std::map<uint32_t, size_t> owner;  // tile -> part
  for (size_t p = 1; p < o.merge.size(); ++p) {
    TileSet set = load_tile_set(o.merge[p]);
    if (!parts.empty() && !(set.header == parts.front().header))
      throw InputError(o.merge[p] + ": a part of a different render than " + o.merge[1] + " (" +
                       first_difference(parts.front().header, set.header) + ")");
    for (const TilePixels& t : set.tiles) {
      auto [it, fresh] = owner.emplace(t.tile, p);
      if (!fresh)
        throw InputError(o.merge[p] + ": tile " + std::to_string(t.tile) + " is also in " + o.merge[it->second] +
                         " (the same shard given twice?)");
    }
    parts.push_back(std::move(set));
  }
  const TileSetHeader& h = parts.front().header;
  std::vector<const TilePixels*> tiles;
  RenderStats stats;
  for (const TileSet& set : parts) {
    for (const TilePixels& t : set.tiles) tiles.push_back(&t);
    stats.add_render(set.stats);
  }
  Film film;
  try {
    film = assemble_film(h, tiles);
  } catch (const InputError& e) {
    throw InputError("--merge: " + std::string(e.what()) + "; give every shard's part");
  }
  check_writable(output);
  if (h.adaptive) check_writable(rate_image_path(output));
  if (!o.variance_file.empty()) check_writable(o.variance_file);
  write_image(output, film, h.png_truncate ? PngQuantization::kTruncate : PngQuantization::kNearest);
  if (h.adaptive) write_sample_rate_image(rate_image_path(output), film);
  if (!o.variance_file.empty()) write_variance_image(o.variance_file, film);
  if (!o.quiet)
    std::printf("Merged %zu parts (%zu tiles) into %s; the shards rendered %llu rays in %.3f s summed\n",
                parts.size(), tiles.size(), output.c_str(), static_cast<unsigned long long>(stats.rays()),
                stats.seconds);
  return 0;
}

}  // namespace pt::cli
