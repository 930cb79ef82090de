// The command line through the pathtracer binary: every bad flag value is one
// exact error line and exit code 2, with no output file; a camera file that
// does not parse and an output that cannot be written are one line and exit
// code 1, reported before rendering starts; and valid values take effect.
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "io/image_output.h"
#include "kernels/simd/isa.h"
#include "io/exr_image.h"
#include "support/run_process.h"
#include "support/test_support.h"

namespace pt {
namespace {

constexpr double kTimeLimit = 60.0;

test::ProcessResult run(const test::ScratchDir& dir, std::vector<std::string> args) {
  return test::run_process(PT_PATHTRACER_BINARY, args, dir.path(), kTimeLimit);
}

/// Exactly one stderr line equal to `expected`, exit `code`, nothing written to `dir`.
void expect_refused(const test::ScratchDir& dir, const std::vector<std::string>& before, const test::ProcessResult& r,
                    int code, const std::string& expected) {
  ASSERT_FALSE(r.timed_out) << "still running after " << kTimeLimit << " s";
  EXPECT_EQ(r.exit_code, code);
  EXPECT_EQ(r.err, expected + "\n");
  EXPECT_EQ(dir.entries(), before) << "an output or temporary file was left behind";
}

// ------------------------------------------------------------- flag values

struct BadFlags {
  std::vector<std::string> args;
  std::string message;  ///< the whole stderr line
};

void PrintTo(const BadFlags& b, std::ostream* os) {
  for (const std::string& a : b.args) *os << a << ' ';
}

const std::vector<BadFlags> kBadFlags = {
    {{"-s", "-5"}, "error: -s: samples per pixel must be an integer from 1 to 16777216, got \"-5\""},
    {{"-s", "0"}, "error: -s: samples per pixel must be an integer from 1 to 16777216, got \"0\""},
    {{"-s", "abc"}, "error: -s: samples per pixel must be an integer from 1 to 16777216, got \"abc\""},
    {{"-s", "1e3"}, "error: -s: samples per pixel must be an integer from 1 to 16777216, got \"1e3\""},
    {{"-s", "0x10"}, "error: -s: samples per pixel must be an integer from 1 to 16777216, got \"0x10\""},
    {{"-s", "99999999999"}, "error: -s: samples per pixel must be an integer from 1 to 16777216, got \"99999999999\""},
    {{"--samples=-3"}, "error: -s: samples per pixel must be an integer from 1 to 16777216, got \"-3\""},
    {{"-s"}, "error: -s: missing value"},
    {{"-s", "-H"}, "error: -s: missing value before -H"},
    {{"-l", "0"}, "error: -l: light samples must be an integer from 1 to 4096, got \"0\""},
    {{"-t", "4x"}, "error: -t: thread count must be an integer from 1 to 1024, got \"4x\""},
    {{"-m", "-1"}, "error: -m: maximum depth must be an integer from 0 to 1024, got \"-1\""},
    {{"-r", "0", "600"}, "error: -r: width must be an integer from 1 to 16384, got \"0\""},
    {{"-r", "800", "-600"}, "error: -r: height must be an integer from 1 to 16384, got \"-600\""},
    {{"-r", "100000", "600"}, "error: -r: width must be an integer from 1 to 16384, got \"100000\""},
    {{"-r", "16384", "16384"}, "error: -r: 16384 x 16384 is more than 134217728 pixels"},
    {{"-r", "800"}, "error: -r: needs 2 values (W H), got 1"},
    {{"-a", "32", "-0.1"}, "error: -a: tolerance must be a number >= 0 (0 turns adaptive sampling off), got \"-0.1\""},
    {{"-a", "32", "nan"}, "error: -a: tolerance must be a number >= 0 (0 turns adaptive sampling off), got \"nan\""},
    {{"-a", "0", "0.05"}, "error: -a: batch size must be an integer from 1 to 16777216, got \"0\""},
    {{"-p", "0", "0", "900", "10"}, "error: -p: region 0 0 900 10 is not inside the 800x600 image"},
    {{"-r", "100", "100", "-p", "50", "50", "51", "10"},
     "error: -p: region 50 50 51 10 is not inside the 100x100 image"},
    {{"-p", "-1", "0", "5", "5"}, "error: -p: region x must be an integer from 0 to 16384, got \"-1\""},
    {{"-p", "0", "0", "0", "5"}, "error: -p: region width must be an integer from 1 to 16384, got \"0\""},
    {{"-p", "1", "2", "3"}, "error: -p: needs 4 values (X Y DX DY), got 3"},
    {{"--engine", "fast"}, "error: --engine: unknown engine \"fast\" (one of: reference, wavefront, megakernel)"},
    {{"--engine", "2"}, "error: --engine: unknown engine \"2\" (one of: reference, wavefront, megakernel)"},
    {{"--bvh", "bvh8"}, "error: --bvh: unknown acceleration structure \"bvh8\" (one of: bvh4, bvh2, none)"},
    {{"--bounces", "all"},
     "error: --bounces: unknown bounce mode \"all\" (one of: accumulate, only-m, direct, indirect)"},
    {{"--rr", "0"}, "error: --rr: continuation probability must be a number in (0, 1], got \"0\""},
    {{"--rr", "1.5"}, "error: --rr: continuation probability must be a number in (0, 1], got \"1.5\""},
    {{"--seed", "-1"}, "error: --seed: seed must be an integer from 0 to 4294967295, got \"-1\""},
    {{"--leaf-size", "0"}, "error: --leaf-size: leaf size must be an integer from 1 to 64, got \"0\""},
    {{"--presplit", "-1"},
     "error: --presplit: pre-splitting budget must be a number from 0 to 16 (extra references per triangle), got "
     "\"-1\""},
    {{"--presplit", "nan"},
     "error: --presplit: pre-splitting budget must be a number from 0 to 16 (extra references per triangle), got "
     "\"nan\""},
    {{"--presplit", "17"},
     "error: --presplit: pre-splitting budget must be a number from 0 to 16 (extra references per triangle), got "
     "\"17\""},
    {{"--trace", "packets"}, "error: --trace: unknown trace mode \"packets\" (one of: queue, single)"},
    {{"--checkpoint-every", "0"},
     "error: --checkpoint-every: checkpoint interval must be a positive number of seconds, got \"0\""},
    {{"--isa", "sse5"}, "error: --isa: unknown instruction set \"sse5\" (one of: auto, sse4.2, avx2, avx512, neon)"},
    {{"-b", "-1"}, "error: -b: lens radius must be a number >= 0 (0: pinhole), got \"-1\""},
    {{"-b", "inf"}, "error: -b: lens radius must be a number >= 0 (0: pinhole), got \"inf\""},
    {{"-d", "0"}, "error: -d: focal distance must be a positive number, got \"0\""},
    {{"-e"}, "error: -e: missing value"},
    {{"--bogus"}, "error: The following argument was not expected: --bogus (see --help)"},
    {{"a.dae", "b.dae"}, "error: The following argument was not expected: b.dae (see --help)"},
    {{"-c", "-q"}, "error: -c: missing value before -q"},
    {{"--engine", "megakernel", "--shade-in-queue-order"},
     "error: --shade-in-queue-order needs the wavefront engine (the only one with queues)"},
};

class BadFlagsTest : public ::testing::TestWithParam<BadFlags> {};

TEST_P(BadFlagsTest, OneExactLineExitCode2NoOutput) {
  test::ScratchDir dir;
  std::vector<std::string> args = {"-q", "-f", "out.png"};
  args.insert(args.end(), GetParam().args.begin(), GetParam().args.end());
  expect_refused(dir, {}, run(dir, args), 2, GetParam().message);
}

INSTANTIATE_TEST_SUITE_P(Table, BadFlagsTest, ::testing::ValuesIn(kBadFlags), [](const auto& info) {
  std::string name = std::to_string(info.index);
  for (const std::string& a : info.param.args) {
    name += '_';
    for (char c : a) name += std::isalnum(static_cast<unsigned char>(c)) ? c : (c == '-' ? 'm' : '_');
  }
  return name;
});

TEST(Flags, OutputThatIsTheSceneFileIsRefused) {
  test::ScratchDir dir;
  std::filesystem::copy_file(PT_DEFAULT_SCENE, dir / "scene.dae");
  std::vector<std::string> before = dir.entries();
  expect_refused(dir, before, run(dir, {"-q", "-f", "scene.dae", "scene.dae"}), 2,
                 "error: -f: the output scene.dae would overwrite the scene file");
}

// ----------------------------------------------------------------- camera files

/// A camera file that does parse: the one a render writes with --write-camera.
std::string valid_camera_file(const test::ScratchDir& dir) {
  test::ProcessResult r = run(dir, {"-q", "-r", "4", "3", "-f", "cam.png", "--write-camera", "cam.txt"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::string text = test::file_bytes(dir / "cam.txt");
  for (const char* f : {"cam.png", "cam_rate.png", "cam.txt"}) std::filesystem::remove(dir / f);
  return text;
}

TEST(CameraFile, ThatDoesNotParseIsOneLineNamingTheFileAndField) {
  test::ScratchDir dir;
  std::string good = valid_camera_file(dir);
  ASSERT_FALSE(good.empty());
  std::string unit_broken = good;
  unit_broken.replace(unit_broken.find("\n1 0 0\n"), 7, "\n2 0 0\n");  // first c2w row: column x no longer unit
  struct Case {
    std::string name, text, message;
  };
  for (const Case& c : {Case{"garbage.txt", "hello world", "camera file field hFov is not a finite number: \"hello\""},
                        Case{"short.txt", "50 35 1.33 0.01", "camera file ends before fClip"},
                        Case{"nan.txt", "nan 35 1 0 1", "camera file field hFov is not a finite number: \"nan\""},
                        Case{"hex.txt", "0x1p5 35 1 0 1", "camera file field hFov is not a finite number: \"0x1p5\""},
                        Case{"fov.txt", "190" + good.substr(good.find(' ')),
                             "camera file fields of view must be between 0 and 180 degrees"},
                        Case{"c2w.txt", unit_broken, "camera file c2w columns must be unit vectors"}}) {
    SCOPED_TRACE(c.name);
    dir.write(c.name, c.text);
    std::vector<std::string> before = dir.entries();
    expect_refused(dir, before, run(dir, {"-q", "-r", "4", "3", "-f", "out.png", "-c", c.name}), 1,
                   "error: " + c.name + ": " + c.message);
  }
  std::filesystem::create_directory(dir / "camdir");
  std::vector<std::string> before = dir.entries();
  expect_refused(dir, before, run(dir, {"-q", "-f", "out.png", "-c", "camdir"}), 1,
                 "error: camdir: is a directory, not a camera file");
  expect_refused(dir, before, run(dir, {"-q", "-f", "out.png", "-c", "missing.txt"}), 1,
                 "error: missing.txt: no such file");
}

TEST(CameraFile, WrittenByARenderIsAccepted) {
  test::ScratchDir dir;
  dir.write("cam.txt", valid_camera_file(dir));
  test::ProcessResult r = run(dir, {"-q", "-r", "4", "3", "-f", "out.png", "-c", "cam.txt"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out.png"));
}

// ------------------------------------------------------------------ thin lens

TEST(ThinLens, ApertureZeroIsThePinholeBitForBit) {
  test::ScratchDir dir;
  const std::vector<std::string> common = {"-q", "-r", "24", "18", "-s", "4", "-m", "2"};
  auto with = [&](std::vector<std::string> extra, const char* out) {
    std::vector<std::string> args = common;
    args.insert(args.end(), extra.begin(), extra.end());
    args.insert(args.end(), {"-f", out});
    test::ProcessResult r = run(dir, args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    return test::file_bytes(dir / out);
  };
  std::string pinhole = with({}, "pinhole.png");
  EXPECT_EQ(with({"-b", "0", "-d", "2.5"}, "b0.png"), pinhole);
  EXPECT_NE(with({"-b", "0.2", "-d", "2.5"}, "lens.png"), pinhole);
}

TEST(ThinLens, TheCameraFileCarriesTheLensAndIsHonoured) {
  test::ScratchDir dir;
  test::ProcessResult r = run(
      dir, {"-q", "-r", "24", "18", "-s", "4", "-b", "0.15", "-d", "3.5", "-f", "a.png", "--write-camera", "cam.txt"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  std::string cam = test::file_bytes(dir / "cam.txt");
  std::istringstream last(cam.substr(cam.find_last_of('\n', cam.size() - 2) + 1));
  float focal = 0, radius = 0;
  last >> focal >> radius;
  EXPECT_EQ(focal, 3.5f) << cam;
  EXPECT_EQ(radius, 0.15f) << cam;
  r = run(dir, {"-q", "-r", "24", "18", "-s", "4", "-c", "cam.txt", "-f", "b.png"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(test::file_bytes(dir / "a.png"), test::file_bytes(dir / "b.png"));
}

// ------------------------------------------------------------ environment maps

TEST(EnvironmentMap, AMapReplacesTheSkyAndABadOneIsOneLineWithNoOutput) {
  test::ScratchDir dir;
  write_exr((dir / "sky.exr").string(), RgbImage{8, 4, std::vector<float3>(32, float3(0.5f, 0.6f, 0.7f))});
  test::ProcessResult r = run(dir, {"-q", "-r", "16", "12", "-s", "4", "-e", "sky.exr", "-f", "lit.png"});
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "lit.png"));
  std::vector<std::string> before = dir.entries();
  expect_refused(dir, before, run(dir, {"-q", "-f", "out.png", "-e", "missing.exr"}), 1,
                 "error: missing.exr: no such file");
  dir.write("junk.exr", "not an image");
  before = dir.entries();
  test::ProcessResult junk = run(dir, {"-q", "-f", "out.png", "-e", "junk.exr"});
  EXPECT_EQ(junk.exit_code, 1);
  EXPECT_EQ(junk.err.rfind("error: junk.exr: ", 0), 0u) << junk.err;
  EXPECT_EQ(std::count(junk.err.begin(), junk.err.end(), '\n'), 1) << junk.err;
  EXPECT_EQ(dir.entries(), before);
}

// ------------------------------------------------------------ unwritable outputs

/// A render that would take hours (16M samples per pixel, adaptive sampling
/// off): finishing within the time limit means it stopped before rendering.
const std::vector<std::string> kEndlessRender = {"-q", "-s", "16777216", "-a", "32", "0", "-r", "800", "600"};

TEST(UnwritableOutput, IsReportedBeforeRenderingStarts) {
  test::ScratchDir dir;
  dir.write("a_file", "x");
  std::filesystem::create_directory(dir / "a_dir");
  std::vector<std::string> before = dir.entries();
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  for (const Case& c :
       {Case{{"-f", "no/such/dir/out.png"},
             "error: no/such/dir/out.png: cannot write output here: No such file or directory"},
        Case{{"-f", "a_file/out.png"}, "error: a_file/out.png: cannot write output here: Not a directory"},
        Case{{"-f", "a_dir"}, "error: a_dir: output path is a directory"},
        Case{{"-f", "out.png", "--write-camera", "no/such/cam.txt"},
             "error: no/such/cam.txt: cannot write output here: No such file or directory"}}) {
    SCOPED_TRACE(c.message);
    std::vector<std::string> args = kEndlessRender;
    args.insert(args.end(), c.args.begin(), c.args.end());
    expect_refused(dir, before, run(dir, args), 1, c.message);
  }
}

TEST(UnwritableOutput, ReadOnlyDirectory) {
  if (geteuid() == 0) GTEST_SKIP() << "running as root: permissions do not stop writing";
  test::ScratchDir dir;
  std::filesystem::create_directory(dir / "ro");
  std::filesystem::permissions(dir / "ro", std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  std::vector<std::string> args = kEndlessRender;
  args.insert(args.end(), {"-f", "ro/out.png"});
  expect_refused(dir, dir.entries(), run(dir, args), 1,
                 "error: ro/out.png: cannot write output here: Permission denied");
}

TEST(ReferenceImage, WhoseHeaderClaimsMoreThanTheFileHoldsIsRefusedWithoutAllocatingIt) {
  test::ScratchDir dir;
  dir.write("huge.pfm", "PF\n65536 65536\n-1.0\n" + std::string(12, '\0'));  // would be 48 GiB of pixels
  std::vector<std::string> before = dir.entries();
  test::ProcessResult r = test::run_process(
      PT_PATHTRACER_BINARY, {"-q", "-r", "4", "3", "--reference", "huge.pfm", "--convergence-csv", "out.csv"},
      dir.path(), kTimeLimit, size_t(1) << 30);
  expect_refused(dir, before, r, 1, "error: huge.pfm: PFM data is truncated");
}

// ------------------------------------------------------ instruction sets

TEST(Flags, ALevelThisBinaryLacksIsRefused) {
  std::string compiled;
  for (Isa c : compiled_isas()) compiled += (compiled.empty() ? "" : ", ") + std::string(isa_name(c));
  for (Isa isa : {Isa::kSse42, Isa::kAvx2, Isa::kAvx512, Isa::kNeon}) {
    bool in_binary = false;
    for (Isa c : compiled_isas()) in_binary = in_binary || c == isa;
    if (in_binary) continue;
    test::ScratchDir dir;
    std::string name(isa_name(isa));
    expect_refused(dir, {}, run(dir, {"-q", "-f", "out.png", "--isa", name}), 2,
                   "error: --isa: this binary is not compiled for " + name + " (it has: " + compiled + ")");
  }
}

TEST(Flags, AnUnknownLevelInPT_ISAIsRefused) {
  ::setenv("PT_ISA", "sse5", 1);
  test::ScratchDir dir;
  test::ProcessResult r = run(dir, {"-q", "-f", "out.png"});
  ::unsetenv("PT_ISA");
  expect_refused(dir, {}, r, 2,
                 "error: PT_ISA: unknown instruction set \"sse5\" (one of: auto, sse4.2, avx2, avx512, neon)");
}

TEST(Flags, EveryLevelTheCpuRunsRendersAndIsNamedInTheReport) {
  for (Isa isa : compiled_isas()) {
    if (!cpu_supports(isa)) continue;
    test::ScratchDir dir;
    std::string name(isa_name(isa));
    test::ProcessResult r = run(dir, {"-r", "8", "6", "-s", "4", "--isa", name, "-f", "out.png"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    std::string expected = "(bvh4, " + name + ", " + std::to_string(isa_lanes(isa)) + " lanes)";
    EXPECT_NE(r.out.find(expected), std::string::npos) << r.out;
  }
}

// --------------------------------------------------------- valid values work

TEST(Flags, PresplitReachesTheBuildAndKeepsTheImage) {
  // --presplit cuts long diagonal triangles into fragments before the BVH4's
  // build (--stats reports its build references): the tree changes, the hits
  // and the image do not.
  PT_REQUIRE_SHARED_SCENES();
  test::ScratchDir dir;
  const std::string scene = test::shared_scene("CBbunny.dae").string();
  auto references = [&](const std::string& budget, const std::string& out) {
    test::ProcessResult r = run(
        dir, {"-t", "2", "-s", "4", "-m", "3", "-r", "64", "48", "--stats", "--presplit", budget, "-f", out, scene});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    unsigned triangles = 0, refs = 0;
    const size_t at = r.out.find("bvh4: ");
    EXPECT_NE(at, std::string::npos) << r.out;
    if (at != std::string::npos)
      std::sscanf(r.out.c_str() + at, "bvh4: %u triangles, %u build references", &triangles, &refs);
    EXPECT_GT(triangles, 0u);
    return std::pair{triangles, refs};
  };
  const auto [plain_triangles, plain_refs] = references("0", "plain.pfm");
  const auto [split_triangles, split_refs] = references("1", "split.pfm");
  EXPECT_EQ(plain_refs, plain_triangles);
  EXPECT_EQ(split_triangles, plain_triangles);
  EXPECT_GT(split_refs, plain_refs + plain_triangles / 2);  // a budget of 1: up to one extra reference per triangle
  std::ifstream a(dir.path() / "plain.pfm", std::ios::binary), b(dir.path() / "split.pfm", std::ios::binary);
  const std::string plain((std::istreambuf_iterator<char>(a)), {}), split((std::istreambuf_iterator<char>(b)), {});
  EXPECT_FALSE(plain.empty());
  EXPECT_EQ(plain, split) << "pre-splitting changed the image";
}

TEST(Flags, ResolutionRegionAndDecimalSamplesTakeEffect) {
  test::ScratchDir dir;
  test::ProcessResult r =
      run(dir, {"-r", "8", "6", "-p", "2", "1", "3", "2", "-s", "016", "-a", "32", "0", "-f", "out.pfm"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("; 96 samples"), std::string::npos) << r.out;  // 3 x 2 pixels x 16 (decimal, not octal 14)
  int w = 0, h = 0;
  std::vector<float3> px = read_pfm(dir / "out.pfm", w, h);
  ASSERT_EQ(w, 8);
  ASSERT_EQ(h, 6);
  bool lit_inside = false;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      bool inside = x >= 2 && x < 5 && y >= 1 && y < 3;
      const float3& p = px[size_t(y) * w + x];
      if (inside) lit_inside |= max_component(p) > 0.0f;
      else EXPECT_EQ(p, float3(0.0f)) << "pixel " << x << "," << y << " is outside the region";
    }
  EXPECT_TRUE(lit_inside);
}

/// The bytes of a file.
std::string file_bytes(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// Renders the built-in scene small with `flags` into `name`.pfm and returns its bytes.
std::string render_pfm(const test::ScratchDir& dir, const std::string& name, std::vector<std::string> flags) {
  std::vector<std::string> args = {"-r", "16", "12", "-s", "8", "-m", "3", "-t", "2", "-q", "-f", name + ".pfm"};
  args.insert(args.end(), flags.begin(), flags.end());
  test::ProcessResult r = run(dir, args);
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return file_bytes(dir / (name + ".pfm"));
}

// The defaults are Sobol points, MIS, roulette at 0.8 and no adaptive
// sampling (no rate image); --cs184-compat's are the course renderer's
// (independent numbers, light sampling, -a 32 0.05, --rr 0.65), and a flag
// given with it still wins.
TEST(Flags, DefaultsAndTheCourseDefaultsOfCs184Compat) {
  test::ScratchDir dir;
  const std::string defaults = render_pfm(dir, "default", {});
  EXPECT_FALSE(std::filesystem::exists(dir / "default_rate.png"));
  EXPECT_EQ(defaults, render_pfm(dir, "explicit",
                                 {"--sampler", "sobol", "--direct", "mis", "--rr", "0.8", "--rr-mode", "fixed", "-a",
                                  "32", "0"}));
  EXPECT_NE(defaults, render_pfm(dir, "light", {"--direct", "light"}));
  const std::string course = render_pfm(dir, "course", {"--cs184-compat"});
  EXPECT_TRUE(std::filesystem::exists(dir / "course_rate.png"));
  EXPECT_EQ(course, render_pfm(dir, "course_explicit",
                               {"--cs184-compat", "--sampler", "independent", "--direct", "light", "-a", "32", "0.05",
                                "--rr", "0.65"}));
  EXPECT_NE(course, render_pfm(dir, "course_sobol", {"--cs184-compat", "--sampler", "sobol"}));
}

// A multi-valued flag takes exactly its values: the scene may follow -r W H.
TEST(Flags, ASceneMayFollowTheValuesOfR) {
  test::ScratchDir dir;
  const std::string scene = std::string(PT_PROJECT_SCENES) + "/cornell_spheres.dae";
  test::ProcessResult r = run(dir, {"-s", "1", "-q", "-f", "out.png", "-a", "16", "0", "-r", "8", "6", scene});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "out.png"));
}

/// The `column` (0-based) of every data row of a CSV file.
std::vector<std::string> csv_column(const std::filesystem::path& p, int column) {
  std::istringstream in(file_bytes(p));
  std::vector<std::string> values;
  std::string line;
  std::getline(in, line);  // header
  while (std::getline(in, line)) {
    std::istringstream fields(line);
    std::string field;
    for (int c = 0; c <= column; ++c) std::getline(fields, field, ',');
    values.push_back(field);
  }
  return values;
}

// Convergence mode: each sample count continues the previous one, or with
// --convergence-restart is rendered from the start; the images, hence the
// errors, are the same bit for bit (a pixel's samples do not depend on how
// the passes were cut), and so are the rays of the last count (the same paths).
TEST(Convergence, RestartingEachCountGivesTheSameErrors) {
  test::ScratchDir dir;
  ASSERT_EQ(run(dir, {"-r", "16", "12", "-s", "64", "-m", "3", "-q", "-f", "ref.pfm"}).exit_code, 0);
  const std::vector<std::string> common = {"-r", "16", "12",     "-s", "8",           "-m",
                                           "3",  "-q", "--seed", "5",  "--reference", "ref.pfm"};
  std::vector<std::string> continued = common, restarted = common;
  continued.insert(continued.end(), {"--convergence-csv", "continued.csv"});
  restarted.insert(restarted.end(), {"--convergence-csv", "restarted.csv", "--convergence-restart"});
  ASSERT_EQ(run(dir, continued).exit_code, 0);
  ASSERT_EQ(run(dir, restarted).exit_code, 0);
  EXPECT_EQ(csv_column(dir / "continued.csv", 1), (std::vector<std::string>{"1", "2", "4", "8"}));
  EXPECT_EQ(csv_column(dir / "continued.csv", 4), csv_column(dir / "restarted.csv", 4));                // rmse
  EXPECT_EQ(csv_column(dir / "continued.csv", 3).back(), csv_column(dir / "restarted.csv", 3).back());  // rays at 8
  test::ProcessResult r = run(dir, {"--convergence-restart"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(r.err, "error: --convergence-restart needs --convergence-csv\n");
}

// --export-scene writes the scene as this renderer reads it and renders
// nothing; an unwritable path is one line before loading.
TEST(ExportScene, WritesTheLoadedSceneAndTheCameraAsJson) {
  test::ScratchDir dir;
  test::ProcessResult r = run(dir, {"-r", "40", "30", "-q", "--export-scene", "scene.json"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"scene.json"});
  const nlohmann::json doc = nlohmann::json::parse(file_bytes(dir / "scene.json"));
  // The built-in Cornell box: 10 wall triangles + the light's 2, two spheres, one area light.
  EXPECT_EQ(doc["triangles"].size(), 12u * 4u);
  EXPECT_EQ(doc["mesh_triangle_count"], 10);
  EXPECT_EQ(doc["spheres"].size(), 2u);
  EXPECT_EQ(doc["area_lights"].size(), 1u);
  EXPECT_EQ(doc["positions"].size(), doc["normals"].size());
  EXPECT_EQ(doc["width"], 40);
  EXPECT_FLOAT_EQ(doc["camera"]["tan_half_vfov"].get<float>(), doc["camera"]["tan_half_hfov"].get<float>() * 30 / 40);
  test::ScratchDir other;
  r = run(other, {"--export-scene", "missing/scene.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("missing/scene.json"), std::string::npos) << r.err;
}

}  // namespace
}  // namespace pt
