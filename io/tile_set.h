// Tiles: the unit of work that MPI ranks and --shard jobs render, and the file
// of finished tiles (a shard's part, an MPI render's checkpoint). A pixel's
// samples depend only on the pixel, the settings and the seed, so a tile holds
// exactly the film values one process rendering the whole image computes for
// it, and tiles pasted together in any order give that process's image bit for
// bit.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "kernels/render/film.h"
#include "kernels/render/render_settings.h"
#include "kernels/render/render_stats.h"

namespace pt {

/// The largest tile edge: a tile's 20 B per pixel stay under MPI's int
/// message size.
inline constexpr int kMaxTileSize = 4096;
/// The most pixels an image may have (as the command line allows).
inline constexpr int64_t kMaxImagePixels = int64_t(1) << 27;

/// The render region (the whole image without -p) cut into square tiles,
/// numbered row by row; edge tiles are cut short.
struct TileGrid {
  Region area;
  int size = 64;  ///< tile edge in pixels
  int columns = 0, rows = 0;

  TileGrid() = default;
  TileGrid(const RenderSettings& rs, int tile_size);
  uint32_t count() const { return uint32_t(columns) * uint32_t(rows); }
  Region tile(uint32_t t) const;
};

/// One tile's film values, row-major inside the tile (20 B per pixel), and
/// how long it took to render (the image's cost map, for load balancing).
struct TilePixels {
  uint32_t tile = 0;
  double seconds = 0.0;
  std::vector<float3> radiance;
  std::vector<uint32_t> samples;
  std::vector<float> variance;
};

TilePixels copy_tile(const Film& film, const TileGrid& grid, uint32_t tile);
void paste_tile(Film& film, const TileGrid& grid, const TilePixels& pixels);

/// A tile as bytes (for a message or a file): id, seconds, pixel count, the arrays.
void append_tile(std::string& out, const TilePixels& t);
/// Takes one tile off the front of `in`. False if the bytes are not a tile of
/// `grid` with values a render of at most `max_samples` samples makes.
bool take_tile(std::string_view& in, const TileGrid& grid, uint32_t max_samples, TilePixels& t);

/// A RenderStats as bytes, and back (false if `in` is too short).
void append_stats(std::string& out, const RenderStats& s);
bool take_stats(std::string_view& in, RenderStats& s);

/// What a tile set is of: everything that must match to merge or resume it.
struct TileSetHeader {
  std::string fingerprint;  ///< render_fingerprint(...) and the tile size
  int32_t width = 0, height = 0;
  uint32_t max_samples = 0;
  int32_t tile_size = 0;
  Region area;
  uint8_t adaptive = 0;      ///< write the sample-rate image beside the output
  uint8_t png_truncate = 0;  ///< PNG values truncated (--cs184-compat)

  TileGrid grid() const;
  bool operator==(const TileSetHeader&) const = default;
};

/// Finished tiles of one render, and the statistics of rendering them.
struct TileSet {
  TileSetHeader header;
  RenderStats stats;
  std::vector<TilePixels> tiles;
};

/// Writes atomically: "PTTILES1", header, stats, tiles, FNV-1a checksum.
void save_tile_set(const std::filesystem::path& path, const TileSet& set);
/// Throws InputError naming the file if it is not a complete, consistent tile
/// set (bad header or checksum, a tile outside the grid or repeated, values
/// no render makes).
TileSet load_tile_set(const std::filesystem::path& path);

/// The image of a complete set of tiles: throws InputError (naming the first
/// missing tile) if some tile of the grid is absent.
Film assemble_film(const TileSetHeader& header, const std::vector<const TilePixels*>& tiles);

}  // namespace pt
