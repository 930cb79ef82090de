// The tile runner (distributed/) with a region renderer whose pixels are a
// known function of their position: a tile carries exactly its region's
// pixels; shards split the tiles with none twice and none missing, and their
// merge is the image of one render bit for bit, whatever the order of the
// parts; the merge refuses parts of another render (naming the first setting
// that differs), a tile in two parts and missing tiles, naming the part; a
// shard stopped part-way is nothing; and a process started without mpirun is
// rank 0 of 1. All exact.
#include <atomic>
#include <set>

#include <gtest/gtest.h>

#include "distributed/mpi_job.h"
#include "distributed/shards.h"
#include "distributed/tile_render.h"
#include "io/scene_error.h"

namespace pt::dist {
namespace {

float3 pixel_value(int x, int y, uint32_t seed) { return {float(x), float(y) * 0.5f, float(seed % 7)}; }

/// Renders the settings' region (or the whole image) with pixel_value, as an
/// engine would: a cropped film when the control asks for one.
struct KnownPixels {
  int calls = 0;
  std::atomic<bool>* cancel_after = nullptr;  ///< set this flag after the first call
  RenderOutput operator()(const RenderSettings& rs, const RenderControl& control) {
    ++calls;
    const Region area = rs.area();
    const uint32_t spp = uint32_t(rs.samples_per_pixel);
    RenderOutput out;
    out.film = control.crop_film ? Film::cropped(area, spp) : Film(rs.width, rs.height, spp);
    for (int y = area.y; y < area.y + area.height; ++y)
      for (int x = area.x; x < area.x + area.width; ++x) {
        out.film.radiance[out.film.index(x, y)] = pixel_value(x, y, rs.seed);
        out.film.samples[out.film.index(x, y)] = spp;
      }
    out.stats.samples = uint64_t(area.width) * area.height * spp;
    out.stats.camera_rays = out.stats.samples;
    out.stats.seconds = 0.001;
    if (cancel_after) cancel_after->store(true);
    return out;
  }
};

RenderSettings settings() { return RenderSettings{.width = 70, .height = 45, .samples_per_pixel = 3, .seed = 5}; }

TileSetHeader header(const RenderSettings& rs, int tile, const std::string& fingerprint = "engine=test s=3") {
  TileSetHeader h;
  h.fingerprint = fingerprint;
  h.width = rs.width;
  h.height = rs.height;
  h.max_samples = uint32_t(rs.samples_per_pixel);
  h.tile_size = tile;
  h.area = TileGrid(rs, tile).area;
  return h;
}

TEST(TileRunner, ATileCarriesExactlyItsRegionsPixels) {
  const RenderSettings rs = settings();
  const TileGrid grid(rs, 16);
  ASSERT_EQ(grid.count(), 5u * 3u);  // 70 x 45 in 16-pixel tiles: partial tiles on the right and bottom
  KnownPixels known;
  for (uint32_t t : {0u, 4u, 14u}) {
    std::optional<RenderedTile> tile = render_tile(std::ref(known), rs, grid, t, nullptr);
    ASSERT_TRUE(tile);
    const Region r = grid.tile(t);
    ASSERT_EQ(tile->pixels.radiance.size(), size_t(r.width) * r.height);
    for (int y = 0; y < r.height; ++y)
      for (int x = 0; x < r.width; ++x)
        ASSERT_EQ(tile->pixels.radiance[size_t(y) * r.width + x], pixel_value(r.x + x, r.y + y, rs.seed));
  }
}

TEST(TileRunner, ShardsMergeIntoTheWholeImageInAnyOrder) {
  const RenderSettings rs = settings();
  KnownPixels known;
  const TileSetHeader h = header(rs, 16);
  std::atomic<bool> cancel{false};
  std::vector<NamedTileSet> parts;
  std::multiset<uint32_t> seen;
  for (uint32_t i = 0; i < 4; ++i) {
    std::optional<TileSet> set = render_shard(std::ref(known), rs, h, i, 4, cancel);
    ASSERT_TRUE(set);
    for (const TilePixels& t : set->tiles) {
      EXPECT_EQ(t.tile % 4, i);
      seen.insert(t.tile);
    }
    parts.push_back({"part" + std::to_string(i), std::move(*set)});
  }
  EXPECT_EQ(seen.size(), h.grid().count());
  EXPECT_EQ(std::set<uint32_t>(seen.begin(), seen.end()).size(), seen.size());
  std::swap(parts[0], parts[3]);
  MergedImage merged = merge_shards(parts);
  const Film whole = known(rs, RenderControl{}).film;
  EXPECT_EQ(merged.film.radiance, whole.radiance);
  EXPECT_EQ(merged.film.samples, whole.samples);
  EXPECT_EQ(merged.tiles, h.grid().count());
  EXPECT_EQ(merged.stats.samples, uint64_t(rs.width) * rs.height * 3);
}

/// The message merge_shards throws for `parts`.
std::string merge_error(const std::vector<NamedTileSet>& parts) {
  try {
    merge_shards(parts);
  } catch (const InputError& e) { return e.what(); }
  return "no error";
}

TEST(TileRunner, TheMergeRefusesOtherRendersRepeatedAndMissingTiles) {
  const RenderSettings rs = settings();
  KnownPixels known;
  std::atomic<bool> cancel{false};
  auto shard = [&](uint32_t i, const TileSetHeader& h) { return *render_shard(std::ref(known), rs, h, i, 2, cancel); };
  const TileSetHeader h = header(rs, 16);
  const TileSet a = shard(0, h), b = shard(1, h);
  EXPECT_EQ(merge_error({{"a.tiles", a}, {"other.tiles", shard(1, header(rs, 16, "engine=test s=4"))}}),
            "other.tiles: a part of a different render than a.tiles (its s=4 against s=3)");
  EXPECT_EQ(merge_error({{"a.tiles", a}, {"t32.tiles", shard(1, header(rs, 32))}}),
            "t32.tiles: a part of a different render than a.tiles (tile size 32 against 16)");
  EXPECT_EQ(merge_error({{"a.tiles", a}, {"b.tiles", b}, {"again.tiles", a}}),
            "again.tiles: tile 0 is also in a.tiles (the same shard given twice?)");
  EXPECT_NE(merge_error({{"a.tiles", a}}).find("--merge: 7 of 15 tiles are missing (the first is tile 1 at 16,0)"),
            std::string::npos)
      << merge_error({{"a.tiles", a}});
}

TEST(TileRunner, AShardStoppedPartWayIsNothing) {
  const RenderSettings rs = settings();
  std::atomic<bool> cancel{false};
  KnownPixels known;
  known.cancel_after = &cancel;  // stops after the first tile
  EXPECT_FALSE(render_shard(std::ref(known), rs, header(rs, 16), 0, 1, cancel));
  EXPECT_EQ(known.calls, 1);
}

TEST(MpiJob, WithoutMpirunAProcessIsRankZeroOfOne) {
  int argc = 1;
  char name[] = "test";
  char* args[] = {name, nullptr};
  char** argv = args;
  MpiJob job(&argc, &argv);
  EXPECT_EQ(job.rank(), 0);
  EXPECT_EQ(job.size(), 1);
  MpiJob::Readiness r = job.agree_ready(true);
  EXPECT_TRUE(r.all);
  EXPECT_TRUE(r.rank0);
}

}  // namespace
}  // namespace pt::dist
