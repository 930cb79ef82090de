// Tile grid geometry, tile bytes and the tile set file.
#include "tile_set.h"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "atomic_file.h"
#include "binary_io.h"
#include "read_file.h"
#include "scene_error.h"

namespace pt {
namespace {

constexpr char kMagic[8] = {'P', 'T', 'T', 'I', 'L', 'E', 'S', '1'};
constexpr uint64_t kMaxTileSetBytes = uint64_t(1) << 34;  // 16 GiB: 20 B per pixel of a 16384^2 image, and slack

template <class T>
void put_array(std::string& out, const std::vector<T>& v) {
  out.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
}

template <class T>
bool take_array(std::string_view& in, std::vector<T>& v, size_t n) {
  if (in.size() / sizeof(T) < n) return false;
  v.resize(n);
  std::memcpy(v.data(), in.data(), n * sizeof(T));
  in.remove_prefix(n * sizeof(T));
  return true;
}

}  // namespace

TileGrid::TileGrid(const RenderSettings& rs, int tile_size) : area(rs.area()), size(tile_size) {
  columns = (area.width + size - 1) / size;
  rows = (area.height + size - 1) / size;
}

Region TileGrid::tile(uint32_t t) const {
  int x = area.x + int(t % uint32_t(columns)) * size, y = area.y + int(t / uint32_t(columns)) * size;
  return {x, y, std::min(size, area.x + area.width - x), std::min(size, area.y + area.height - y)};
}

TilePixels copy_tile(const Film& film, const TileGrid& grid, uint32_t tile) {
  Region r = grid.tile(tile);
  TilePixels t;
  t.tile = tile;
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x) {
      size_t i = film.index(x, y);
      t.radiance.push_back(film.radiance[i]);
      t.samples.push_back(film.samples[i]);
      t.variance.push_back(film.variance[i]);
    }
  return t;
}

void paste_tile(Film& film, const TileGrid& grid, const TilePixels& t) {
  Region r = grid.tile(t.tile);
  size_t k = 0;
  for (int y = r.y; y < r.y + r.height; ++y)
    for (int x = r.x; x < r.x + r.width; ++x, ++k) {
      size_t i = film.index(x, y);
      film.radiance[i] = t.radiance[k];
      film.samples[i] = t.samples[k];
      film.variance[i] = t.variance[k];
    }
}

void append_tile(std::string& out, const TilePixels& t) {
  put(out, t.tile);
  put(out, t.seconds);
  put(out, static_cast<uint32_t>(t.radiance.size()));
  put_array(out, t.radiance);
  put_array(out, t.samples);
  put_array(out, t.variance);
}

bool take_tile(std::string_view& in, const TileGrid& grid, uint32_t max_samples, TilePixels& t) {
  uint32_t n = 0;
  if (!take(in, t.tile) || !take(in, t.seconds) || !take(in, n) || t.tile >= grid.count()) return false;
  if (!std::isfinite(t.seconds) || t.seconds < 0.0) return false;
  Region r = grid.tile(t.tile);
  if (n != uint32_t(r.width) * uint32_t(r.height)) return false;
  if (!take_array(in, t.radiance, n) || !take_array(in, t.samples, n) || !take_array(in, t.variance, n)) return false;
  for (uint32_t k = 0; k < n; ++k)
    if (!is_finite(t.radiance[k]) || t.samples[k] > max_samples || !std::isfinite(t.variance[k]) ||
        t.variance[k] < 0.0f)
      return false;
  return true;
}

void append_stats(std::string& out, const RenderStats& s) {
  put(out, s.camera_rays), put(out, s.bounce_rays), put(out, s.shadow_rays), put(out, s.intersection_tests);
  put(out, s.samples), put(out, s.invalid_samples), put(out, s.seconds);
}

bool take_stats(std::string_view& in, RenderStats& s) {
  return take(in, s.camera_rays) && take(in, s.bounce_rays) && take(in, s.shadow_rays) &&
         take(in, s.intersection_tests) && take(in, s.samples) && take(in, s.invalid_samples) && take(in, s.seconds);
}

TileGrid TileSetHeader::grid() const {
  return TileGrid(RenderSettings{.width = width, .height = height, .region = area}, tile_size);
}

void save_tile_set(const std::filesystem::path& path, const TileSet& set) {
  const TileSetHeader& h = set.header;
  std::string out(kMagic, sizeof kMagic);
  put(out, static_cast<uint32_t>(h.fingerprint.size()));
  out += h.fingerprint;
  put(out, h.width), put(out, h.height), put(out, h.max_samples), put(out, h.tile_size);
  put(out, h.area.x), put(out, h.area.y), put(out, h.area.width), put(out, h.area.height);
  put(out, h.adaptive), put(out, h.png_truncate);
  append_stats(out, set.stats);
  put(out, static_cast<uint32_t>(set.tiles.size()));
  for (const TilePixels& t : set.tiles) append_tile(out, t);
  close_frame(out);
  write_file_atomically(path, out);
}

TileSet load_tile_set(const std::filesystem::path& path) {
  std::string data = read_regular_file(path, "tile set", kMaxTileSetBytes);
  auto bad = [&](const std::string& what) { return InputError(path.string() + ": not a usable tile set: " + what); };
  std::string_view in = frame_body(data, kMagic, bad, " (not written by --shard or --checkpoint under mpirun)");
  TileSet set;
  TileSetHeader& h = set.header;
  uint32_t fp_len = 0, count = 0;
  if (!take(in, fp_len) || in.size() < fp_len) throw bad("truncated header");
  h.fingerprint.assign(in.substr(0, fp_len));
  in.remove_prefix(fp_len);
  if (!take(in, h.width) || !take(in, h.height) || !take(in, h.max_samples) || !take(in, h.tile_size) ||
      !take(in, h.area.x) || !take(in, h.area.y) || !take(in, h.area.width) || !take(in, h.area.height) ||
      !take(in, h.adaptive) || !take(in, h.png_truncate) || !take_stats(in, set.stats) || !take(in, count))
    throw bad("truncated header");
  const Region& a = h.area;
  if (h.width < 1 || h.height < 1 || int64_t(h.width) * h.height > kMaxImagePixels || h.tile_size < 1 ||
      h.tile_size > kMaxTileSize || a.x < 0 || a.y < 0 || a.width < 1 || a.height < 1 ||
      int64_t(a.x) + a.width > h.width || int64_t(a.y) + a.height > h.height || h.adaptive > 1 || h.png_truncate > 1)
    throw bad("image size, region or tile size out of range");
  TileGrid grid = h.grid();
  constexpr size_t kSmallestTile = 4 + 8 + 4 + 20;  // id, seconds, pixel count, one pixel
  if (count > grid.count() || count > in.size() / kSmallestTile) throw bad("more tiles than the image has");
  std::vector<bool> seen(grid.count(), false);
  for (uint32_t k = 0; k < count; ++k) {  // read before allocated: the file's size bounds what is allocated
    TilePixels t;
    if (!take_tile(in, grid, h.max_samples, t))
      throw bad("a tile that does not fit the image or holds impossible values");
    if (seen[t.tile]) throw bad("tile " + std::to_string(t.tile) + " appears twice");
    seen[t.tile] = true;
    set.tiles.push_back(std::move(t));
  }
  if (!in.empty()) throw bad("trailing bytes after the last tile");
  return set;
}

Film assemble_film(const TileSetHeader& h, const std::vector<const TilePixels*>& tiles) {
  TileGrid grid = h.grid();
  std::vector<bool> have(grid.count(), false);
  for (const TilePixels* t : tiles) have[t->tile] = true;
  auto missing = std::find(have.begin(), have.end(), false);
  if (missing != have.end()) {
    size_t n = size_t(std::count(have.begin(), have.end(), false));
    Region r = grid.tile(uint32_t(missing - have.begin()));
    throw InputError(std::to_string(n) + " of " + std::to_string(grid.count()) +
                     " tiles are missing (the first is tile " + std::to_string(missing - have.begin()) + " at " +
                     std::to_string(r.x) + "," + std::to_string(r.y) + ")");
  }
  Film film(h.width, h.height, h.max_samples);
  for (const TilePixels* t : tiles) paste_tile(film, grid, *t);
  return film;
}

}  // namespace pt
