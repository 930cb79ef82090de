// Rendering split into tiles: the tile grid and tile set file; --shard parts
// merged in any order (and with any tile size) equal the single-process image
// byte for byte, and mismatched or incomplete parts are refused; under
// mpirun (when the build has MPI and mpirun is installed) 2 and 3 ranks give
// the single-process PNG and PFM byte for byte, a killed rank ends the job
// without a final image and the checkpoint resumes to the uninterrupted image,
// and SIGINT leaves a partial image. The signals are sent once the job has
// saved its first checkpoint (an event), never after a delay.
#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <thread>

#include "io/binary_io.h"
#include "io/scene_error.h"
#include "io/tile_set.h"
#include "support/run_process.h"
#include "support/test_support.h"

namespace pt {
namespace {

using test::file_bytes;
using test::run_process;
using test::ScratchDir;

const std::string kBinary = PT_PATHTRACER_BINARY;
constexpr double kTimeout = 120.0;

/// Every pixel of the region lies in exactly one tile, and no pixel outside it in any.
TEST(TileGrid, TilesCoverTheRegionExactlyOnce) {
  for (int size : {1, 7, 16, 64}) {
    RenderSettings rs{.width = 53, .height = 37, .region = Region{5, 3, 41, 30}};
    TileGrid grid(rs, size);
    std::vector<int> cover(size_t(rs.width) * rs.height, 0);
    for (uint32_t t = 0; t < grid.count(); ++t) {
      Region r = grid.tile(t);
      ASSERT_GT(r.width, 0);
      ASSERT_GT(r.height, 0);
      for (int y = r.y; y < r.y + r.height; ++y)
        for (int x = r.x; x < r.x + r.width; ++x) ++cover[size_t(y) * rs.width + x];
    }
    for (int y = 0; y < rs.height; ++y)
      for (int x = 0; x < rs.width; ++x) {
        bool inside = x >= 5 && x < 46 && y >= 3 && y < 33;
        ASSERT_EQ(cover[size_t(y) * rs.width + x], inside ? 1 : 0)
            << "tile size " << size << " pixel " << x << "," << y;
      }
  }
}

TileSet small_set() {
  TileSet set;
  set.header.fingerprint = "test render";
  set.header.width = 20;
  set.header.height = 10;
  set.header.max_samples = 8;
  set.header.tile_size = 8;
  set.header.area = Region{0, 0, 20, 10};
  TileGrid grid = set.header.grid();
  Film film(20, 10, 8);
  for (size_t i = 0; i < film.radiance.size(); ++i) {
    film.radiance[i] = float3(float(i), 0.5f, 1.0f / float(i + 1));
    film.samples[i] = uint32_t(i % 9);
    film.variance[i] = float(i) * 1e-3f;
  }
  for (uint32_t t = 0; t < grid.count(); ++t) set.tiles.push_back(copy_tile(film, grid, t));
  set.stats.camera_rays = 12345;
  set.stats.seconds = 1.5;
  return set;
}

TEST(TileSet, RoundTripsAndAssemblesTheFilm) {
  ScratchDir dir;
  TileSet set = small_set();
  save_tile_set(dir / "a.tiles", set);
  TileSet back = load_tile_set(dir / "a.tiles");
  EXPECT_TRUE(back.header == set.header);
  EXPECT_EQ(back.stats.camera_rays, 12345u);
  EXPECT_EQ(back.stats.seconds, 1.5);
  std::vector<const TilePixels*> tiles;
  for (auto it = back.tiles.rbegin(); it != back.tiles.rend(); ++it) tiles.push_back(&*it);  // any order
  Film film = assemble_film(back.header, tiles);
  for (size_t i = 0; i < film.radiance.size(); ++i) {
    ASSERT_EQ(film.radiance[i].x, float(i));
    ASSERT_EQ(film.radiance[i].z, 1.0f / float(i + 1));
    ASSERT_EQ(film.samples[i], uint32_t(i % 9));
    ASSERT_EQ(film.variance[i], float(i) * 1e-3f);
  }
  tiles.pop_back();
  EXPECT_THROW(assemble_film(back.header, tiles), InputError);
}

/// Each damaged file is refused with a message naming it.
TEST(TileSet, RefusesDamagedAndImpossibleFiles) {
  ScratchDir dir;
  TileSet set = small_set();
  save_tile_set(dir / "good.tiles", set);
  std::string good = file_bytes(dir / "good.tiles");
  auto refused = [&](const std::string& name, const std::string& bytes, const std::string& why) {
    std::filesystem::path p = dir.write(name, bytes);
    try {
      load_tile_set(p);
      ADD_FAILURE() << name << " was accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(p.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(why), std::string::npos) << e.what();
    }
  };
  refused("empty.tiles", "", "bad header");
  refused("short.tiles", good.substr(0, good.size() / 2), "checksum");
  std::string flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  refused("flipped.tiles", flipped, "checksum");

  TileSet twice = set;
  twice.tiles.push_back(twice.tiles.front());
  save_tile_set(dir / "twice.tiles", twice);
  refused("twice2.tiles", file_bytes(dir / "twice.tiles"), "more tiles than the image has");
  twice.tiles.erase(twice.tiles.begin() + 1);
  save_tile_set(dir / "twice.tiles", twice);
  refused("twice3.tiles", file_bytes(dir / "twice.tiles"), "appears twice");

  TileSet nan = set;
  nan.tiles[1].radiance[3].y = std::numeric_limits<float>::quiet_NaN();
  save_tile_set(dir / "nan.tiles", nan);
  refused("nan2.tiles", file_bytes(dir / "nan.tiles"), "impossible values");
  TileSet too_many = set;
  too_many.tiles[0].samples[0] = 9;  // more than max_samples
  save_tile_set(dir / "many.tiles", too_many);
  refused("many2.tiles", file_bytes(dir / "many.tiles"), "impossible values");
  TileSet outside = set;
  outside.header.area = Region{15, 0, 10, 10};  // past the image's right edge
  save_tile_set(dir / "outside.tiles", outside);
  refused("outside2.tiles", file_bytes(dir / "outside.tiles"), "out of range");
  TileSet huge_tile = set;
  huge_tile.header.tile_size = 2147473648;  // the grid's arithmetic would overflow
  save_tile_set(dir / "huge.tiles", huge_tile);
  refused("huge2.tiles", file_bytes(dir / "huge.tiles"), "out of range");
  TileSet huge_image = set;
  huge_image.header.width = huge_image.header.height = 16384;  // 2^28 pixels: more than any render makes
  save_tile_set(dir / "big.tiles", huge_image);
  refused("big2.tiles", file_bytes(dir / "big.tiles"), "out of range");

  // A tile count larger than the file could hold is refused before anything is allocated for it.
  TileSet no_tiles = set;
  no_tiles.tiles.clear();
  no_tiles.header.width = no_tiles.header.height = 8192;
  no_tiles.header.area = Region{0, 0, 8192, 8192};
  no_tiles.header.tile_size = 1;
  save_tile_set(dir / "count.tiles", no_tiles);
  std::string bytes = file_bytes(dir / "count.tiles");
  uint32_t count = 1u << 26;
  std::memcpy(bytes.data() + bytes.size() - 12, &count, 4);  // the count precedes the checksum
  uint64_t sum = fnv1a(bytes.data(), bytes.size() - 8);
  std::memcpy(bytes.data() + bytes.size() - 8, &sum, 8);
  refused("count2.tiles", bytes, "more tiles than the image has");
}

/// The flags of the small renders below.
std::vector<std::string> with(std::vector<std::string> base, const std::vector<std::string>& more) {
  base.insert(base.end(), more.begin(), more.end());
  return base;
}

/// The built-in scene at 64x48: `samples` per pixel, adaptive sampling -a 8 0.05 unless `adaptive` is false.
std::vector<std::string> small(const std::string& samples = "16", bool adaptive = true) {
  return {"-r", "64", "48", "-s", samples, "-l", "2", "-m", "4", "-a", adaptive ? "8" : "64", adaptive ? "0.05" : "0",
          "-q"};
}
const std::vector<std::string> kSmall = small();

void expect_same_file(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::string x = file_bytes(a), y = file_bytes(b);
  EXPECT_FALSE(x.empty());
  EXPECT_TRUE(x == y) << a << " and " << b << " differ";
}

TEST(Shards, MergedInAnyOrderAndWithAnyTileSizeEqualTheSingleProcessImage) {
  ScratchDir dir;
  for (const char* ext : {".png", ".pfm"}) {
    ASSERT_EQ(
        run_process(kBinary, with(kSmall, {"-t", "2", "-f", std::string("one") + ext}), dir.path(), kTimeout).exit_code,
        0);
  }
  for (const char* tile : {"16", "7", "64"}) {
    for (int i = 0; i < 3; ++i) {
      auto r = run_process(kBinary,
                           with(kSmall, {"-t", "1", "--tile", tile, "--shard", std::to_string(i) + "/3", "-f",
                                         "part" + std::to_string(i) + ".tiles"}),
                           dir.path(), kTimeout);
      ASSERT_EQ(r.exit_code, 0) << r.err;
    }
    for (const char* ext : {".png", ".pfm"}) {
      std::string out = std::string("merged") + tile + ext;
      auto r = run_process(kBinary, {"--merge", out, "part2.tiles", "part0.tiles", "part1.tiles", "-q"}, dir.path(),
                           kTimeout);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      expect_same_file(dir / (std::string("one") + ext), dir / out);
      if (std::string(ext) == ".png")
        expect_same_file(dir / "one_rate.png", dir / (std::string("merged") + tile + "_rate.png"));
    }
    auto r = run_process(kBinary, {"--merge", "again.png", "part1.tiles", "part0.tiles", "part2.tiles", "-q"},
                         dir.path(), kTimeout);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_same_file(dir / "one.png", dir / "again.png");
  }
}

/// Tiles are rendered by the same engines as whole images: every engine and
/// lighting mode, with adaptive sampling, gives the same bits either way.
TEST(Shards, EveryEngineAndLightingModeMergesToTheSingleProcessImage) {
  ScratchDir dir;
  const std::vector<std::vector<std::string>> variants = {
      {"--engine", "megakernel"},
      {"--engine", "reference"},
      {"--direct", "mis"},
      {"-H"},
      {"--sampler", "independent", "--rr-mode", "throughput"},
      {"--normals"},
      {"--bounces", "indirect"},
      {"-b", "0.05", "-d", "3"},
  };
  int k = 0;
  for (const auto& variant : variants) {
    std::string tag = std::to_string(k++);
    auto base = with(small("8"), variant);
    ASSERT_EQ(run_process(kBinary, with(base, {"-t", "2", "-f", "one" + tag + ".png"}), dir.path(), kTimeout).exit_code,
              0);
    for (int i = 0; i < 2; ++i)
      ASSERT_EQ(run_process(kBinary,
                            with(base, {"-t", "1", "--tile", "20", "--shard", std::to_string(i) + "/2", "-f",
                                        "p" + tag + "_" + std::to_string(i) + ".tiles"}),
                            dir.path(), kTimeout)
                    .exit_code,
                0);
    auto r = run_process(kBinary, {"--merge", "m" + tag + ".png", "p" + tag + "_1.tiles", "p" + tag + "_0.tiles", "-q"},
                         dir.path(), kTimeout);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    SCOPED_TRACE(testing::PrintToString(variant));
    expect_same_file(dir / ("one" + tag + ".png"), dir / ("m" + tag + ".png"));
  }
}

TEST(Shards, ARegionMergesToTheSingleProcessRegion) {
  ScratchDir dir;
  auto base = with(kSmall, {"-p", "9", "5", "40", "30"});
  ASSERT_EQ(run_process(kBinary, with(base, {"-f", "one.png"}), dir.path(), kTimeout).exit_code, 0);
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(run_process(kBinary,
                          with(base, {"--tile", "12", "--shard", std::to_string(i) + "/2", "-f",
                                      "p" + std::to_string(i) + ".tiles"}),
                          dir.path(), kTimeout)
                  .exit_code,
              0);
  ASSERT_EQ(run_process(kBinary, {"--merge", "m.png", "p1.tiles", "p0.tiles", "-q"}, dir.path(), kTimeout).exit_code,
            0);
  expect_same_file(dir / "one.png", dir / "m.png");
}

TEST(Shards, MismatchedMissingOrRepeatedPartsAreRefused) {
  ScratchDir dir;
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(run_process(kBinary,
                          with(kSmall, {"--tile", "16", "--shard", std::to_string(i) + "/2", "-f",
                                        "p" + std::to_string(i) + ".tiles"}),
                          dir.path(), kTimeout)
                  .exit_code,
              0);
  auto s8 = small("8");
  ASSERT_EQ(
      run_process(kBinary, with(s8, {"--tile", "16", "--shard", "1/2", "-f", "other.tiles"}), dir.path(), kTimeout)
          .exit_code,
      0);
  ASSERT_EQ(
      run_process(kBinary, with(kSmall, {"--tile", "32", "--shard", "1/2", "-f", "tile32.tiles"}), dir.path(), kTimeout)
          .exit_code,
      0);
  ASSERT_EQ(run_process(
                kBinary,
                with(kSmall, {"--tile", "16", "--sampler", "independent", "--shard", "1/2", "-f", "independent.tiles"}),
                dir.path(), kTimeout)
                .exit_code,
            0);
  struct Case {
    std::vector<std::string> parts;
    std::string message;
  };
  const Case cases[] = {
      {{"p0.tiles", "other.tiles"},
       "error: other.tiles: a part of a different render than p0.tiles (its s=8 against s=16)"},
      {{"p0.tiles", "tile32.tiles"},
       "error: tile32.tiles: a part of a different render than p0.tiles (tile size 32 against 16)"},
      {{"p0.tiles", "independent.tiles"},
       "error: independent.tiles: a part of a different render than p0.tiles (its sampler=0 against sampler=1)"},
      {{"p0.tiles"},
       "error: --merge: 6 of 12 tiles are missing (the first is tile 1 at 16,0); give every shard's part"},
      {{"p0.tiles", "p1.tiles", "p0.tiles"},
       "error: p0.tiles: tile 0 is also in p0.tiles (the same shard given twice?)"},
      {{"p0.tiles", "missing.tiles"}, "missing.tiles"},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args = {"--merge", "out.png"};
    args.insert(args.end(), c.parts.begin(), c.parts.end());
    auto r = run_process(kBinary, args, dir.path(), kTimeout);
    EXPECT_EQ(r.exit_code, 1) << c.message;
    std::vector<std::string> lines = test::lines_of(r.err);
    ASSERT_EQ(lines.size(), 1u) << r.err;
    EXPECT_NE(lines[0].find(c.message), std::string::npos) << lines[0];
    EXPECT_FALSE(std::filesystem::exists(dir / "out.png")) << "no output from a refused merge";
  }
}

TEST(Shards, BadShardFlagsAreRefused) {
  ScratchDir dir;
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"--shard", "3"}, "error: --shard: expected I/N (this job's share I of N, counted from 0), got \"3\""},
      {{"--shard", "3/3"}, "error: --shard: shard index I of I/N must be an integer from 0 to 2, got \"3\""},
      {{"--shard", "0/0"}, "error: --shard: shard count N of I/N must be an integer from 1 to 1048576, got \"0\""},
      {{"--tile", "0"}, "error: --tile: tile size must be an integer from 1 to 4096, got \"0\""},
      {{"--merge", "out.png"}, "error: --merge: needs 2 values (OUT PART...), got 1"},
      {{"scene.dae", "--merge", "out.png", "a.tiles"},
       "error: --merge assembles parts made by --shard and takes no scene"},
      {{"--shard", "0/2", "--checkpoint", "c.bin"}, "error: --shard renders its share in one go"},
      {{"--shard", "0/2", "--stats"},
       "error: --stats reports one whole-image render in one process; not with --shard or mpirun"},
  };
  for (const auto& [args, message] : cases) {
    auto r = run_process(kBinary, args, dir.path(), kTimeout);
    EXPECT_NE(r.exit_code, 0);
    std::vector<std::string> lines = test::lines_of(r.err);
    ASSERT_EQ(lines.size(), 1u) << r.err;
    EXPECT_EQ(lines[0].rfind(message, 0), 0u) << lines[0];
  }
  EXPECT_TRUE(dir.entries().empty());
}

// ------------------------------------------------------------------ mpirun

/// mpirun with the shared-memory transport: what one machine needs, and it
/// starts in a tenth of a second where Open MPI's default probing takes 0.3 s.
std::vector<std::string> mpirun(int ranks, const std::vector<std::string>& args) {
  std::vector<std::string> cmd = {"--oversubscribe",     "--mca", "pml", "ob1", "--mca", "btl", "self,vader", "-np",
                                  std::to_string(ranks), kBinary};
  cmd.insert(cmd.end(), args.begin(), args.end());
  return cmd;
}

#define PT_REQUIRE_MPI()                                                          \
  do {                                                                            \
    if (!PT_WITH_MPI) GTEST_SKIP() << "built without MPI (PT_MPI=OFF)";           \
    if (std::string(PT_MPIEXEC).empty()) GTEST_SKIP() << "no mpirun";             \
    setenv("OMPI_ALLOW_RUN_AS_ROOT", "1", 1); /* containers and CI run as root */ \
    setenv("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1", 1);                             \
  } while (0)

void expect_ranks_give_the_single_process_image(const std::vector<std::string>& base, const std::string& tile) {
  ScratchDir dir;
  ASSERT_EQ(
      run_process(kBinary, with(base, {"-t", "2", "-f", "one.png", "--variance", "one_var.pfm"}), dir.path(), kTimeout)
          .exit_code,
      0);
  ASSERT_EQ(run_process(kBinary, with(base, {"-t", "2", "-f", "one.pfm"}), dir.path(), kTimeout).exit_code, 0);
  for (int ranks : {2, 3}) {
    std::string n = std::to_string(ranks);
    auto r = run_process(PT_MPIEXEC,
                         mpirun(ranks, with(base, {"-t", "1", "--tile", tile, "-f", "mpi" + n + ".png", "--variance",
                                                   "var" + n + ".pfm"})),
                         dir.path(), kTimeout);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_same_file(dir / "one.png", dir / ("mpi" + n + ".png"));
    expect_same_file(dir / "one_var.pfm", dir / ("var" + n + ".pfm"));
    r = run_process(PT_MPIEXEC, mpirun(ranks, with(base, {"-t", "1", "--tile", tile, "-f", "mpi" + n + ".pfm"})),
                    dir.path(), kTimeout);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    expect_same_file(dir / "one.pfm", dir / ("mpi" + n + ".pfm"));
  }
}

TEST(Mpi, TwoAndThreeRanksGiveTheSingleProcessImageOfTheBuiltInScene) {
  PT_REQUIRE_MPI();
  expect_ranks_give_the_single_process_image(kSmall, "16");
}

TEST(Mpi, TwoAndThreeRanksGiveTheSingleProcessImageOfCBbunny) {
  PT_REQUIRE_MPI();
  PT_REQUIRE_SHARED_SCENES();
  expect_ranks_give_the_single_process_image(
      {test::shared_scene("CBbunny.dae").string(), "-r", "96", "72", "-s", "16", "-l", "2", "-m", "5", "-q"}, "24");
}

TEST(Mpi, TheEndReportNamesTheRanksAndSumsTheirRays) {
  PT_REQUIRE_MPI();
  ScratchDir dir;
  auto base = small("16", false);
  base.pop_back();  // not -q: the report is what is checked
  auto one = run_process(kBinary, with(base, {"-t", "1", "-f", "one.png"}), dir.path(), kTimeout);
  auto two = run_process(PT_MPIEXEC, mpirun(2, with(base, {"-t", "1", "-f", "two.png"})), dir.path(), kTimeout);
  ASSERT_EQ(two.exit_code, 0) << two.err;
  auto rays = [](const std::string& out) {
    size_t at = out.find(" rays traced");
    size_t from = out.rfind("; ", at);
    return out.substr(from + 2, at - from - 2);
  };
  EXPECT_NE(two.out.find(" on 2 MPI ranks "), std::string::npos) << two.out;
  EXPECT_EQ(rays(one.out), rays(two.out)) << "the same samples and paths, so the same ray counts";
  EXPECT_EQ(test::lines_of(two.out).size(), test::lines_of(one.out).size()) << "rank 1 prints nothing:\n" << two.out;
}

/// Waits until `path` exists: true then; false once `give_up` is set or after a
/// minute (a guard against a job that never gets there, not a measure of speed).
bool wait_for_file(const std::filesystem::path& path, const std::atomic<bool>& give_up) {
  for (int i = 0; i < 6000 && !give_up; ++i) {
    if (std::filesystem::exists(path)) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return std::filesystem::exists(path);
}

/// Pids of the pathtracer processes that are rank `rank` of the mpirun job
/// running in `cwd` (its ranks inherit its working directory; other tests'
/// jobs may run at the same time in theirs).
std::vector<pid_t> pids_of_rank(int rank, const std::filesystem::path& cwd) {
  std::vector<pid_t> pids;
  for (const auto& entry : std::filesystem::directory_iterator("/proc")) {
    std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    std::error_code ec;
    if (std::filesystem::read_symlink(entry.path() / "cwd", ec) != cwd) continue;
    std::ifstream env(entry.path() / "environ", std::ios::binary);
    std::string text((std::istreambuf_iterator<char>(env)), std::istreambuf_iterator<char>());
    std::ifstream exe_cmd(entry.path() / "cmdline", std::ios::binary);
    std::string cmd((std::istreambuf_iterator<char>(exe_cmd)), std::istreambuf_iterator<char>());
    if (cmd.rfind(kBinary, 0) == 0 &&
        text.find("OMPI_COMM_WORLD_RANK=" + std::to_string(rank) + '\0') != std::string::npos)
      pids.push_back(pid_t(std::stol(name)));
  }
  return pids;
}

TEST(Mpi, AKilledRankEndsTheJobAndTheCheckpointResumesToTheUninterruptedImage) {
  PT_REQUIRE_MPI();
  ScratchDir dir;
  auto base = with(small("2048", false), {"--tile", "8"});
  std::atomic<bool> ended{false};
  std::thread killer([&] {
    // Kill rank 1 once rank 0 has saved some finished tiles.
    if (!wait_for_file(dir / "state.tiles", ended)) return;
    for (bool killed = false; !killed && !ended;)
      for (pid_t pid : pids_of_rank(1, std::filesystem::canonical(dir.path()))) killed = kill(pid, SIGKILL) == 0;
  });
  auto r = run_process(
      PT_MPIEXEC,
      mpirun(3, with(base, {"-t", "1", "-f", "out.png", "--checkpoint", "state.tiles", "--checkpoint-every", "0.05"})),
      dir.path(), kTimeout);
  ended = true;
  killer.join();
  EXPECT_FALSE(r.timed_out) << "the job ends once a rank is lost, never hangs";
  ASSERT_TRUE(std::filesystem::exists(dir / "state.tiles")) << r.err;
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("process rank 1 "), std::string::npos) << "mpirun names the lost rank:\n" << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png")) << "no final image from a job that lost a rank";
  EXPECT_TRUE(std::filesystem::exists(dir / "out.partial.png"));
  TileSet saved = load_tile_set(dir / "state.tiles");
  EXPECT_GT(saved.tiles.size(), 0u);
  EXPECT_LT(saved.tiles.size(), saved.header.grid().count()) << "killed mid-render";

  r = run_process(PT_MPIEXEC, mpirun(3, with(base, {"-t", "1", "-f", "out.png", "--checkpoint", "state.tiles"})),
                  dir.path(), kTimeout);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "state.tiles")) << "a finished render removes its checkpoint";
  ASSERT_EQ(run_process(kBinary, with(base, {"-t", "2", "-f", "one.png"}), dir.path(), kTimeout).exit_code, 0);
  expect_same_file(dir / "one.png", dir / "out.png");
}

TEST(Mpi, SigintToMpirunLeavesAPartialImageAndNoFinalOne) {
  PT_REQUIRE_MPI();
  ScratchDir dir;
  test::BackgroundProcess job(
      PT_MPIEXEC,
      mpirun(2, with(small("8192", false), {"--tile", "8", "-t", "1", "-f", "out.png", "--checkpoint", "state.tiles",
                                            "--checkpoint-every", "0.05"})),
      dir.path());
  // A saved checkpoint means every rank is past its start-up (the ranks agree
  // they are ready before the first tile), with its stop handler installed, and
  // that one of the 48 tiles is done: the signal lands early in the render.
  std::atomic<bool> never{false};
  ASSERT_TRUE(wait_for_file(dir / "state.tiles", never)) << job.err();
  test::ProcessResult r = job.stop(SIGINT, std::chrono::milliseconds(60000));
  EXPECT_FALSE(r.timed_out) << "the job ends on SIGINT";
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.err.find("interrupted: wrote the "), std::string::npos) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out.partial.png")) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out.png"));
}

TEST(Mpi, AFailureEveryRankSharesIsReportedOnceAndEndsTheJob) {
  PT_REQUIRE_MPI();
  ScratchDir dir;
  auto r = run_process(PT_MPIEXEC, mpirun(3, {"missing.dae", "-q"}), dir.path(), kTimeout);
  EXPECT_NE(r.exit_code, 0);
  std::vector<std::string> ours;
  for (const std::string& line : test::lines_of(r.err))
    if (line.rfind("error: ", 0) == 0) ours.push_back(line);
  ASSERT_EQ(ours.size(), 1u) << r.err;
  EXPECT_NE(ours[0].find("missing.dae"), std::string::npos) << ours[0];
  EXPECT_TRUE(dir.entries().empty());
}

}  // namespace
}  // namespace pt
