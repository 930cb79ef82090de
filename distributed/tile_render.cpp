// render_tile.
#include "tile_render.h"

namespace pt::dist {

std::optional<RenderedTile> render_tile(const RegionRenderer& render, const RenderSettings& rs, const TileGrid& grid,
                                        uint32_t t, const std::atomic<bool>* cancel) {
  RenderSettings tile_rs = rs;
  tile_rs.region = grid.tile(t);
  RenderControl control;
  control.cancel = cancel;
  control.crop_film = true;  // the tile's pixels only, whatever the image's size
  RenderOutput out = render(tile_rs, control);
  if (out.cancelled || control.cancelled()) return std::nullopt;
  RenderedTile tile{copy_tile(out.film, grid, t), out.stats};
  tile.pixels.seconds = out.stats.seconds;
  return tile;
}

}  // namespace pt::dist
