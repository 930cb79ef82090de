// tile_set_header, run_shard and run_merge.
#include "shard_merge.h"

#include <cstdio>

#include "distributed/shards.h"
#include "io/atomic_file.h"
#include "io/checkpoint.h"
#include "io/image_output.h"
#include "progress_bar.h"
#include "render_outputs.h"

namespace pt::cli {

TileSetHeader tile_set_header(const Options& o, const Scene& scene, const Camera& camera) {
  const RenderSettings& rs = o.settings;
  TileSetHeader h;
  h.fingerprint = render_fingerprint(engine_name(o.engine), scene, camera, rs) + " bvh=" + accel_name(o.accel) +
                  " tile=" + std::to_string(o.tile_size);
  h.width = rs.width;
  h.height = rs.height;
  h.max_samples = static_cast<uint32_t>(rs.samples_per_pixel);
  h.tile_size = o.tile_size;
  h.area = TileGrid(rs, o.tile_size).area;
  h.adaptive = rs.adaptive() ? 1 : 0;
  h.png_truncate = o.cs184_png ? 1 : 0;
  return h;
}

dist::RegionRenderer region_renderer(const EngineRunner& engine) {
  return [&engine](const RenderSettings& rs, const RenderControl& control) { return engine.render(rs, control); };
}

bool run_shard(const Options& o, const Scene& scene, const Camera& camera, const EngineRunner& engine,
               const std::filesystem::path& output, const std::atomic<bool>& cancel) {
  ProgressBar bar(!o.quiet);
  std::optional<TileSet> set =
      dist::render_shard(region_renderer(engine), o.settings, tile_set_header(o, scene, camera),
                         uint32_t(o.shard_index), uint32_t(o.shard_count), cancel, [&](double f) { bar.update(f); });
  bar.finish();
  if (!set) {
    std::fprintf(stderr, "interrupted: shard %d/%d not written (a shard is written whole; run it again)\n",
                 o.shard_index, o.shard_count);
    return false;
  }
  save_tile_set(output, *set);
  if (!o.quiet)
    std::printf("Shard %d/%d: %zu of %u tiles in %.3f s, %llu rays; wrote %s\n", o.shard_index, o.shard_count,
                set->tiles.size(), set->header.grid().count(), set->stats.seconds,
                static_cast<unsigned long long>(set->stats.rays()), output.c_str());
  return true;
}

int run_merge(const Options& o) {
  const std::filesystem::path output = o.merge.front();
  std::vector<dist::NamedTileSet> parts;
  for (size_t p = 1; p < o.merge.size(); ++p) parts.push_back({o.merge[p], load_tile_set(o.merge[p])});
  dist::MergedImage merged = dist::merge_shards(parts);
  const TileSetHeader& h = merged.header;
  check_writable(output);
  if (h.adaptive) check_writable(rate_image_path(output));
  if (!o.variance_file.empty()) check_writable(o.variance_file);
  write_image(output, merged.film, h.png_truncate ? PngQuantization::kTruncate : PngQuantization::kNearest);
  if (h.adaptive) write_sample_rate_image(rate_image_path(output), merged.film);
  if (!o.variance_file.empty()) write_variance_image(o.variance_file, merged.film);
  if (!o.quiet)
    std::printf("Merged %zu parts (%zu tiles) into %s; the shards rendered %llu rays in %.3f s summed\n", parts.size(),
                merged.tiles, output.c_str(), static_cast<unsigned long long>(merged.stats.rays()),
                merged.stats.seconds);
  return 0;
}

}  // namespace pt::cli
