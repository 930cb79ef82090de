// render_tile and tile_set_header.
#include "tile_render.h"

#include "io/checkpoint.h"

namespace pt::cli {

std::optional<RenderedTile> render_tile(const EngineRunner& engine, const RenderSettings& rs, const TileGrid& grid,
                                        uint32_t t, const std::atomic<bool>* cancel) {
  RenderSettings tile_rs = rs;
  tile_rs.region = grid.tile(t);
  RenderControl control;
  control.cancel = cancel;
  control.crop_film = true;  // the tile's pixels only, whatever the image's size
  RenderOutput out = engine.render(tile_rs, control);
  if (out.cancelled || control.cancelled()) return std::nullopt;
  RenderedTile tile{copy_tile(out.film, grid, t), out.stats};
  tile.pixels.seconds = out.stats.seconds;
  return tile;
}

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

}  // namespace pt::cli
