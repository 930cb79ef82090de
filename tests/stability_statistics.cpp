// Film statistics for the stability tests.
#include "stability_statistics.h"

#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

namespace pt::test {

ImageMean image_mean(const Film& film) {
  double sum = 0.0, var = 0.0;
  for (size_t i = 0; i < film.radiance.size(); ++i) {
    sum += illuminance(film.radiance[i]);
    var += film.variance[i];
  }
  double n = static_cast<double>(film.radiance.size());
  return {sum / n, std::sqrt(var) / n};
}

double per_sample_variance(const Film& film) {
  double sum = 0.0;
  for (size_t i = 0; i < film.variance.size(); ++i) sum += double(film.variance[i]) * film.samples[i];
  return sum / static_cast<double>(film.variance.size());
}

double mean_difference_z(const Film& a, const Film& b) {
  ImageMean ma = image_mean(a), mb = image_mean(b);
  double se = std::sqrt(ma.standard_error * ma.standard_error + mb.standard_error * mb.standard_error);
  return se > 0.0 ? (ma.mean - mb.mean) / se : (ma.mean == mb.mean ? 0.0 : INFINITY);
}

double stouffer_z(const Film& a, const Film& b) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < a.radiance.size(); ++i) {
    double var = double(a.variance[i]) + b.variance[i];
    if (var <= 0.0) continue;
    sum += (illuminance(a.radiance[i]) - illuminance(b.radiance[i])) / std::sqrt(var);
    ++count;
  }
  return count ? sum / std::sqrt(double(count)) : 0.0;
}

void expect_same_image_within_noise(const Film& a, const Film& b, const std::string& what) {
  size_t n = a.radiance.size(), over = 0, noiseless_mismatch = 0;
  double worst = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double ya = illuminance(a.radiance[i]), yb = illuminance(b.radiance[i]);
    double var = double(a.variance[i]) + b.variance[i];
    if (var <= 0.0) {
      noiseless_mismatch += std::fabs(ya - yb) > 1e-5 * std::max(1.0, std::fabs(ya));
      continue;
    }
    double z = std::fabs(ya - yb) / std::sqrt(var);
    over += z > 3.29;
    worst = std::max(worst, z);
  }
  double bound = n * 0.001 + 5.0 * std::sqrt(n * 0.001);
  double z_image = stouffer_z(a, b);
  EXPECT_LE(double(over), bound) << what << ": " << over << " of " << n << " pixels beyond |z| = 3.29";
  EXPECT_LT(worst, 6.5) << what << ": a pixel differs by |z| = " << worst;
  EXPECT_EQ(noiseless_mismatch, 0u) << what << ": noiseless pixels differ";
  EXPECT_LT(std::fabs(z_image), 5.0) << what << ": image means differ, Stouffer Z = " << z_image;
  std::printf("  %s: Stouffer Z %.2f, %zu/%zu pixels beyond |z| = 3.29 (bound %.1f), max |z| %.2f\n", what.c_str(),
              z_image, over, n, bound, worst);
}

Film scaled_film(const Film& film, float factor) {
  Film f = film;
  for (float3& c : f.radiance) c *= factor;
  return f;
}

}  // namespace pt::test
