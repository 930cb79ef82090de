// --target-error, --time and --error-image through the pathtracer binary:
// bad values are one line and exit 2 with nothing written; a render stopped
// by either rule stops at a power-of-two sample count, says which, and writes
// exactly the bytes `-s <that count>` writes; a target not met within -s is a
// warning and the -s image; the combinations that cannot keep their guarantees
// (tiles, the reference engine, convergence runs) are refused in one line.
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/image_output.h"
#include "support/run_process.h"
#include "support/test_support.h"

namespace pt {
namespace {

constexpr double kTimeLimit = 120.0;

test::ProcessResult run(const test::ScratchDir& dir, std::vector<std::string> args,
                        std::vector<std::string> environment = {}) {
  return test::run_process(PT_PATHTRACER_BINARY, args, dir.path(), kTimeLimit, 0, environment);
}

/// A small render of the default scene into `output` with `extra` flags.
std::vector<std::string> small_render(const std::string& output, std::vector<std::string> extra) {
  std::vector<std::string> args = {"-r", "48", "36", "-m", "3", "-t", "2", "-f", output};
  args.insert(args.end(), extra.begin(), extra.end());
  return args;
}

/// The N of "Stopped at N samples per pixel" in `out`, or -1.
long stopped_at(const std::string& out) {
  std::smatch m;
  static const std::regex line("Stopped at ([0-9]+) samples per pixel");
  return std::regex_search(out, m, line) ? std::stol(m[1]) : -1;
}

/// The relative RMSE of the "estimated error:" line, or -1.
double estimated_relative_rmse(const std::string& out) {
  std::smatch m;
  static const std::regex line("estimated error: relative RMSE ([0-9.eE+-]+), RMSE ([0-9.eE+-]+)\n");
  return std::regex_search(out, m, line) ? std::stod(m[1]) : -1.0;
}

bool is_power_of_two(long n) { return n > 0 && (n & (n - 1)) == 0; }

struct BadValue {
  std::vector<std::string> args;
  std::string message;
};

TEST(StopRules, BadValuesAreOneLineAndNothingIsWritten) {
  const std::vector<BadValue> cases = {
      {{"--target-error", "0"},
       "error: --target-error: target relative RMSE must be a positive number (e.g. 0.01 for 1%), got \"0\""},
      {{"--target-error", "-0.1"},
       "error: --target-error: target relative RMSE must be a positive number (e.g. 0.01 for 1%), got \"-0.1\""},
      {{"--target-error", "nan"},
       "error: --target-error: target relative RMSE must be a positive number (e.g. 0.01 for 1%), got \"nan\""},
      {{"--time", "-1"}, "error: --time: time limit must be a positive number of seconds, got \"-1\""},
      {{"--time", "0"}, "error: --time: time limit must be a positive number of seconds, got \"0\""},
      {{"--time", "inf"}, "error: --time: time limit must be a positive number of seconds, got \"inf\""},
      {{"--target-error", "0.1", "--engine", "reference"},
       "error: --target-error needs a pass-based engine (--engine wavefront or megakernel)"},
      {{"--error-image", "e.pfm", "--engine", "reference"},
       "error: --error-image needs a pass-based engine (--engine wavefront or megakernel)"},
      {{"--time", "5", "--shard", "0/2"}, "error: --time needs the whole image in one process; not with --shard"},
      {{"--target-error", "0.1", "--reference", "r.pfm", "--convergence-csv", "c.csv"},
       "error: --target-error and --convergence-csv do not go together (it renders every power of two)"},
  };
  for (const BadValue& c : cases) {
    test::ScratchDir dir;
    const std::vector<std::string> before = dir.entries();
    test::ProcessResult r = run(dir, small_render("out.png", c.args));
    ASSERT_FALSE(r.timed_out);
    EXPECT_EQ(r.exit_code, 2) << c.message;
    EXPECT_EQ(r.err, c.message + "\n");
    EXPECT_EQ(dir.entries(), before) << c.message << ": a file was written";
  }
}

TEST(StopRules, EveryRenderOfFourSamplesOrMorePrintsOneEstimateLine) {
  test::ScratchDir dir;
  test::ProcessResult r = run(dir, small_render("out.png", {"-s", "16"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  size_t count = 0;
  for (const std::string& l : test::lines_of(r.out)) count += l.rfind("estimated error: ", 0) == 0;
  EXPECT_EQ(count, 1u) << r.out;
  EXPECT_GT(estimated_relative_rmse(r.out), 0.0) << r.out;
  test::ProcessResult one = run(dir, small_render("one.png", {"-s", "2"}));
  ASSERT_EQ(one.exit_code, 0) << one.err;
  EXPECT_NE(one.out.find("estimated error: not available (it needs 4 samples per pixel or more)\n"), std::string::npos)
      << one.out;
}

// A target between the estimates at 16 and 64 samples stops at a power of two
// between them, and the image is byte for byte the one -s of that count writes.
TEST(StopRules, TargetErrorStopsAtAPowerOfTwoWithTheImageOfThatCount) {
  test::ScratchDir dir;
  test::ProcessResult at16 = run(dir, small_render("a16.pfm", {"-s", "16"}));
  test::ProcessResult at64 = run(dir, small_render("a64.pfm", {"-s", "64"}));
  ASSERT_EQ(at16.exit_code, 0) << at16.err;
  ASSERT_EQ(at64.exit_code, 0) << at64.err;
  const double e16 = estimated_relative_rmse(at16.out), e64 = estimated_relative_rmse(at64.out);
  ASSERT_GT(e16, e64) << "the estimate does not fall from 16 to 64 samples";
  const double target = 0.5 * (e16 + e64);
  test::ProcessResult r = run(
      dir, small_render("t.pfm", {"-s", "1024", "--target-error", std::to_string(target), "--error-image", "err.pfm"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const long n = stopped_at(r.out);
  EXPECT_TRUE(is_power_of_two(n)) << r.out;
  EXPECT_GT(n, 16) << r.out;
  EXPECT_LE(n, 64) << r.out;
  EXPECT_LE(estimated_relative_rmse(r.out), target) << r.out;
  EXPECT_NE(r.out.find("met --target-error"), std::string::npos) << r.out;
  test::ProcessResult same = run(dir, small_render("s.pfm", {"-s", std::to_string(n)}));
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(test::file_bytes(dir.path() / "t.pfm"), test::file_bytes(dir.path() / "s.pfm"));
  // The error image: one value per pixel, finite and not negative.
  int w = 0, h = 0;
  std::vector<float3> err = read_pfm(dir.path() / "err.pfm", w, h);
  EXPECT_EQ(w, 48);
  EXPECT_EQ(h, 36);
  for (const float3& e : err) ASSERT_TRUE(std::isfinite(e.x) && e.x >= 0.0f && e.x == e.y && e.y == e.z);
}

// With adaptive sampling the sample-rate image is the one of -s N as well
// (samples taken over N, not over the -s the render was allowed).
TEST(StopRules, TargetErrorWithAdaptiveSamplingWritesTheRateImageOfThatCount) {
  test::ScratchDir dir;
  test::ProcessResult r = run(dir, small_render("t.png", {"-s", "1024", "-a", "4", "0.05", "--target-error", "0.08"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const long n = stopped_at(r.out);
  ASSERT_TRUE(is_power_of_two(n)) << r.out;
  ASSERT_LT(n, 1024) << r.out;
  test::ProcessResult same = run(dir, small_render("s.png", {"-s", std::to_string(n), "-a", "4", "0.05"}));
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(test::file_bytes(dir.path() / "t.png"), test::file_bytes(dir.path() / "s.png"));
  EXPECT_EQ(test::file_bytes(dir.path() / "t_rate.png"), test::file_bytes(dir.path() / "s_rate.png"));
}

TEST(StopRules, TargetNotMetWithinSamplesIsAWarningAndTheImageOfSamples) {
  test::ScratchDir dir;
  test::ProcessResult r = run(dir, small_render("t.png", {"-s", "8", "--target-error", "1e-9"}));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(stopped_at(r.out), 8) << r.out;
  EXPECT_EQ(r.err.rfind("warning: --target-error 1e-09 not reached within -s 8 (estimated relative RMSE ", 0), 0u)
      << r.err;
  EXPECT_EQ(test::lines_of(r.err).size(), 1u) << r.err;
  test::ProcessResult same = run(dir, small_render("s.png", {"-s", "8"}));
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(test::file_bytes(dir.path() / "t.png"), test::file_bytes(dir.path() / "s.png"));
}

// On a clock where a sample per pixel takes 1 s (PT_TEST_SECONDS_PER_SAMPLE),
// --time 10 stops at 8: 16 samples would pass 10 s, 8 did not. The image is
// the one -s 8 writes.
TEST(StopRules, TimeStopsAtTheLastPowerOfTwoThatFitsWithTheImageOfThatCount) {
  test::ScratchDir dir;
  test::ProcessResult r =
      run(dir, small_render("t.pfm", {"-s", "256", "--time", "10"}), {"PT_TEST_SECONDS_PER_SAMPLE=1"});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const long n = stopped_at(r.out);
  ASSERT_EQ(n, 8) << r.out;
  EXPECT_NE(r.out.find("twice the samples would pass --time"), std::string::npos) << r.out;
  test::ProcessResult same = run(dir, small_render("s.pfm", {"-s", std::to_string(n)}));
  ASSERT_EQ(same.exit_code, 0) << same.err;
  EXPECT_EQ(test::file_bytes(dir.path() / "t.pfm"), test::file_bytes(dir.path() / "s.pfm"));
}

// Ctrl-C (the PT_TEST_SIGINT_AFTER_PASS hook, after the pass that reaches 4
// samples) saves the checkpoint; the resumed render stops at the same count as
// an uninterrupted one and writes the same bytes.
TEST(StopRules, TargetErrorResumedFromACheckpointStopsWhereAnUninterruptedRenderStops) {
  test::ScratchDir dir;
  const std::vector<std::string> flags = {"-s", "1024", "--target-error", "0.08", "--checkpoint", "state.ckpt"};
  test::ProcessResult whole = run(dir, small_render("whole.pfm", {"-s", "1024", "--target-error", "0.08"}));
  ASSERT_EQ(whole.exit_code, 0) << whole.err;
  const long n = stopped_at(whole.out);
  ASSERT_GT(n, 4) << whole.out;
  test::ProcessResult cut = run(dir, small_render("resumed.pfm", flags), {"PT_TEST_SIGINT_AFTER_PASS=3"});
  ASSERT_EQ(cut.exit_code, 130) << cut.err;
  ASSERT_TRUE(std::filesystem::exists(dir.path() / "state.ckpt"));
  test::ProcessResult resumed = run(dir, small_render("resumed.pfm", flags));
  ASSERT_EQ(resumed.exit_code, 0) << resumed.err;
  EXPECT_NE(resumed.out.find("Resuming from state.ckpt (4 samples per pixel done)"), std::string::npos) << resumed.out;
  EXPECT_EQ(stopped_at(resumed.out), n) << resumed.out;
  EXPECT_EQ(test::file_bytes(dir.path() / "resumed.pfm"), test::file_bytes(dir.path() / "whole.pfm"));
}

}  // namespace
}  // namespace pt
