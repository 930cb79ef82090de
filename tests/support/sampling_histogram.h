// Histograms for the samplers' chi-square tests: unit directions binned by
// (cos theta, phi) around a pole, with an overflow bin (expected count 0) that
// catches samples outside the domain, and the uniform [0, 1) inputs the
// samplers are fed (std::mt19937, independent of the renderer's generator).
#pragma once

#include <cmath>
#include <cstdint>
#include <functional>
#include <numbers>
#include <random>
#include <vector>

namespace pt::test {

/// Uniform floats in [0, 1) with 24 random bits, from a fixed-seed mt19937.
class UniformSource {
 public:
  explicit UniformSource(uint32_t seed) : rng_(seed) {}
  float next() { return static_cast<float>(rng_() >> 8) * 0x1p-24f; }

 private:
  std::mt19937 rng_;
};

/// Directions binned by z = cos(theta) in [z_min, 1] (nz equal bins) and
/// phi = atan2(y, x) in [0, 2 pi) (nphi equal bins); the last bin counts
/// directions with z < z_min or a non-finite component.
class DirectionHistogram {
 public:
  DirectionHistogram(int nz, int nphi, double z_min) : nz_(nz), nphi_(nphi), z_min_(z_min), counts_(nz * nphi + 1) {}

  void add(double x, double y, double z) {
    double phi = std::atan2(y, x);
    if (phi < 0) phi += 2 * std::numbers::pi;
    int iz = static_cast<int>((z - z_min_) / (1.0 - z_min_) * nz_);
    int ip = static_cast<int>(phi / (2 * std::numbers::pi) * nphi_);
    if (!(z >= z_min_ && z <= 1.0) || !std::isfinite(phi)) {
      ++counts_.back();
      return;
    }
    counts_[std::min(iz, nz_ - 1) * nphi_ + std::min(ip, nphi_ - 1)] += 1.0;
  }

  /// Expected counts for n samples when the probability of the bin
  /// [z0, z1] x [phi0, phi1] is `mass(z0, z1, phi0, phi1)`; the overflow bin expects 0.
  std::vector<double> expected(double n, const std::function<double(double, double, double, double)>& mass) const {
    std::vector<double> e(counts_.size(), 0.0);
    for (int i = 0; i < nz_; ++i)
      for (int j = 0; j < nphi_; ++j) {
        double z0 = z_min_ + (1.0 - z_min_) * i / nz_, z1 = z_min_ + (1.0 - z_min_) * (i + 1) / nz_;
        double p0 = 2 * std::numbers::pi * j / nphi_, p1 = 2 * std::numbers::pi * (j + 1) / nphi_;
        e[i * nphi_ + j] = n * mass(z0, z1, p0, p1);
      }
    return e;
  }

  const std::vector<double>& counts() const { return counts_; }

 private:
  int nz_, nphi_;
  double z_min_;
  std::vector<double> counts_;
};

}  // namespace pt::test
