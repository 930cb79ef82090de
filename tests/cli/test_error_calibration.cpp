// The render's own error estimate against the true error: the project's two
// scenes at 128x96, at -m 1 and -m 5, at 16, 64 and 256 samples per pixel,
// four seeds each, against a reference of two independent halves (seeds of
// their own) whose noise, measured from the halves' difference, is taken out
// of the measured error (independent renders add their mean squared errors).
//
// Claims, checked together so that an estimator off by 1.5x either way fails:
//   the geometric mean over every case and seed of estimate / true is in
//     [0.8, 1.25] (a 1.5x error moves it out unless it was already 1.2 or
//     0.83 off);
//   every case (scene, depth, samples): the geometric mean over the seeds is
//     in [0.5, 2]. Not [0.67, 1.5]: the true error does not fall evenly from
//     one power of two to the next (at 16 samples cornell_spheres -m 5 at
//     this size is 1.7 times below the trend of its neighbours, for every
//     seed), and the estimate follows the trend.
// Confidence: one seed's log ratio spreads with a standard deviation of 0.15
// to 0.3 between seeds (measured over six seeds at 160x120 and 64x48); over
// four seeds that is 0.08 to 0.15, and over all 48 renders under 0.05 (they
// are not independent across cases, so more, but the overall band is 4.5
// standard deviations of 0.05 wide on either side). The test also shows the
// claims reject the estimate scaled by 1.5 and by 1/1.5.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "io/atomic_file.h"
#include "io/image_output.h"
#include "support/run_process.h"
#include "support/test_support.h"

namespace pt {
namespace {

constexpr double kTimeLimit = 900.0;
constexpr int kRefHalfSamples = 4096;
constexpr int kSeeds = 4;

test::ProcessResult run(const test::ScratchDir& dir, std::vector<std::string> args) {
  return test::run_process(PT_PATHTRACER_BINARY, args, dir.path(), kTimeLimit);
}

struct Case {
  std::string name;            ///< scene, depth and samples
  std::vector<double> ratios;  ///< estimate / true, one per seed
};

double geometric_mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += std::log(x);
  return std::exp(s / double(v.size()));
}

/// Whether the ratios, each multiplied by `scale`, meet the claims above.
bool calibrated(const std::vector<Case>& cases, double scale, std::string* why = nullptr) {
  std::vector<double> all;
  for (const Case& c : cases) {
    const double g = scale * geometric_mean(c.ratios);
    if (!(g >= 0.5 && g <= 2.0)) {
      if (why) *why = c.name + ": " + std::to_string(g);
      return false;
    }
    for (double r : c.ratios) all.push_back(scale * r);
  }
  const double g = geometric_mean(all);
  if (why) *why = "geometric mean over all " + std::to_string(g);
  return g >= 0.8 && g <= 1.25;
}

/// (spp, rmse against the reference, est_rmse) of the convergence CSV's rows.
struct Row {
  int spp;
  double measured, estimate;
};
std::vector<Row> rows_of(const std::string& csv) {
  std::vector<Row> out;
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);  // method,spp,seconds,rays,rmse,rel_mse,mean_bias,est_rmse,est_rel_rmse
  while (std::getline(in, line)) {
    std::vector<std::string> f;
    std::stringstream ls(line);
    for (std::string x; std::getline(ls, x, ',');) f.push_back(x);
    if (f.size() == 9 && !f[7].empty()) out.push_back({std::stoi(f[1]), std::stod(f[4]), std::stod(f[7])});
  }
  return out;
}

/// Renders the two halves of the reference, writes their average as ref.pfm
/// and returns its mean squared error: |h1 - h2|^2 / 4 over pixels and channels.
double make_reference(const test::ScratchDir& dir, const std::vector<std::string>& common) {
  std::vector<std::vector<float3>> halves;
  int w = 0, h = 0;
  for (int half = 0; half < 2; ++half) {
    const std::string name = "half" + std::to_string(half) + ".pfm";
    std::vector<std::string> args = {
        "-s", std::to_string(kRefHalfSamples), "--seed", std::to_string(1000003 + half), "-q", "-f", name};
    args.insert(args.end(), common.begin(), common.end());
    test::ProcessResult r = run(dir, args);
    EXPECT_EQ(r.exit_code, 0) << r.err;
    halves.push_back(read_pfm(dir.path() / name, w, h));
  }
  std::vector<float3> average(halves[0].size());
  double se = 0.0;
  for (size_t i = 0; i < average.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      average[i][c] = 0.5f * (halves[0][i][c] + halves[1][i][c]);
      const double d = double(halves[0][i][c]) - halves[1][i][c];
      se += d * d;
    }
  write_file_atomically(dir.path() / "ref.pfm", encode_pfm(w, h, average));
  return se / (3.0 * double(average.size())) / 4.0;
}

TEST(ErrorCalibration, EstimateMatchesTheTrueErrorOnTheProjectScenes) {
  std::vector<Case> cases;
  for (const char* scene : {"cornell_spheres.dae", "cornell_materials.dae"})
    for (int depth : {1, 5}) {
      test::ScratchDir dir;
      const std::vector<std::string> common = {
          "-r", "128", "96", "-m", std::to_string(depth), "-t", "2", test::project_scene(scene).string()};
      const double ref_mse = make_reference(dir, common);
      std::vector<Case> here;
      for (int spp : {16, 64, 256})
        here.push_back({std::string(scene) + " -m " + std::to_string(depth) + " " + std::to_string(spp) + " spp", {}});
      for (int seed = 0; seed < kSeeds; ++seed) {
        std::vector<std::string> conv = {
            "-s", "256", "--seed", std::to_string(seed), "--reference", "ref.pfm", "--convergence-csv", "c.csv", "-q"};
        conv.insert(conv.end(), common.begin(), common.end());
        test::ProcessResult r = run(dir, conv);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        for (const Row& row : rows_of(test::file_bytes(dir.path() / "c.csv"))) {
          const int k = row.spp == 16 ? 0 : row.spp == 64 ? 1 : row.spp == 256 ? 2 : -1;
          if (k < 0) continue;
          const double truth = std::sqrt(std::max(0.0, row.measured * row.measured - ref_mse));
          here[size_t(k)].ratios.push_back(row.estimate / truth);
        }
      }
      for (const Case& c : here) ASSERT_EQ(c.ratios.size(), size_t(kSeeds)) << c.name;
      cases.insert(cases.end(), here.begin(), here.end());
    }
  std::ostringstream table;
  for (const Case& c : cases) {
    table << c.name << ": geometric mean " << geometric_mean(c.ratios) << " (";
    for (double r : c.ratios) table << " " << r;
    table << " )\n";
  }
  std::string why;
  EXPECT_TRUE(calibrated(cases, 1.0, &why)) << why << "\n" << table.str();
  // The same claims reject an estimator off by 1.5x either way.
  EXPECT_FALSE(calibrated(cases, 1.5, &why)) << why << "\n" << table.str();
  EXPECT_FALSE(calibrated(cases, 1.0 / 1.5, &why)) << why << "\n" << table.str();
  std::printf("%s", table.str().c_str());
}

}  // namespace
}  // namespace pt
