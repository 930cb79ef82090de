// Chi-square tail probability (regularised upper incomplete gamma Q(a, x), by
// its series below a + 1 and Lentz's continued fraction above), Pearson's test,
// the mean / standard error helpers, and film statistics.
#include "support/statistics.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include <gtest/gtest.h>

namespace pt::test {
namespace {

constexpr int kMaxIterations = 100000;
constexpr double kEps = 1e-15;

/// P(a, x) by the series x^a e^-x / Gamma(a + 1) * sum x^n / ((a+1)...(a+n)); x < a + 1.
double lower_gamma_series(double a, double x) {
  double term = 1.0 / a, sum = term;
  for (int n = 1; n < kMaxIterations; ++n) {
    term *= x / (a + n);
    sum += term;
    if (std::fabs(term) < std::fabs(sum) * kEps) break;
  }
  return sum * std::exp(-x + a * std::log(x) - std::lgamma(a));
}

/// Q(a, x) by the continued fraction (modified Lentz); x >= a + 1.
double upper_gamma_fraction(double a, double x) {
  constexpr double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < kMaxIterations; ++i) {
    double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::fabs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::fabs(c) < tiny) c = tiny;
    d = 1.0 / d;
    double delta = d * c;
    h *= delta;
    if (std::fabs(delta - 1.0) < kEps) break;
  }
  return std::exp(-x + a * std::log(x) - std::lgamma(a)) * h;
}

}  // namespace

double chi_square_tail(double x, double dof) {
  if (!(x > 0.0)) return 1.0;
  double a = 0.5 * dof, h = 0.5 * x;
  return h < a + 1.0 ? 1.0 - lower_gamma_series(a, h) : upper_gamma_fraction(a, h);
}

ChiSquareResult chi_square_test(std::span<const double> observed, std::span<const double> expected) {
  ChiSquareResult r;
  double pooled_obs = 0.0, pooled_exp = 0.0, worst = -1.0;
  size_t worst_bin = 0;
  int bins = 0;
  bool impossible = false;
  for (size_t i = 0; i < observed.size(); ++i) {
    if (expected[i] == 0.0) {
      impossible |= observed[i] > 0.0;
      continue;
    }
    if (expected[i] < 5.0) {
      pooled_obs += observed[i];
      pooled_exp += expected[i];
      continue;
    }
    double d = observed[i] - expected[i], contribution = d * d / expected[i];
    r.statistic += contribution;
    ++bins;
    if (contribution > worst) {
      worst = contribution;
      worst_bin = i;
    }
  }
  if (pooled_exp > 0.0) {
    double d = pooled_obs - pooled_exp;
    r.statistic += d * d / pooled_exp;
    ++bins;
  }
  r.dof = bins - 1;
  r.p_value = impossible ? 0.0 : (r.dof > 0 ? chi_square_tail(r.statistic, r.dof) : 1.0);
  std::ostringstream s;
  s << "chi2 = " << r.statistic << " with " << r.dof << " dof, p = " << r.p_value
    << (impossible ? " (samples in a bin of expected count 0)" : "") << "; worst bin " << worst_bin << ": observed "
    << observed[worst_bin] << ", expected " << expected[worst_bin];
  r.summary = s.str();
  return r;
}

MeanError mean_and_error(std::span<const double> values) {
  MeanError m;
  m.n = values.size();
  if (m.n == 0) return m;
  double sum = 0.0;
  for (double v : values) sum += v;
  m.mean = sum / m.n;
  if (m.n < 2) return m;
  double ss = 0.0;
  for (double v : values) ss += (v - m.mean) * (v - m.mean);
  m.standard_error = std::sqrt(ss / (m.n - 1) / m.n);
  return m;
}

double z_score(const MeanError& m, double expected) {
  double d = m.mean - expected;
  if (m.standard_error > 0.0) return d / m.standard_error;
  if (d == 0.0) return 0.0;
  return d > 0.0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
}

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

double stouffer_detectable_bias(const Film& a, const Film& b) {
  double sum = 0.0;
  size_t count = 0;
  for (size_t i = 0; i < a.radiance.size(); ++i) {
    double var = double(a.variance[i]) + b.variance[i], y = illuminance(a.radiance[i]);
    if (var <= 0.0) continue;
    ++count;
    if (std::sqrt(var) > 1e-4 * std::fabs(y)) sum += y / std::sqrt(var);
  }
  return sum > 0.0 ? (kZ5 + kZ95) * std::sqrt(double(count)) / sum : INFINITY;
}

void expect_same_image_within_noise(const Film& a, const Film& b, const std::string& what) {
  size_t n = a.radiance.size(), over = 0, noiseless_mismatch = 0, worst_pixel = 0;
  double worst = 0.0;
  for (size_t i = 0; i < n; ++i) {
    double ya = illuminance(a.radiance[i]), yb = illuminance(b.radiance[i]);
    double var = double(a.variance[i]) + b.variance[i];
    if (var <= 0.0) {
      noiseless_mismatch += std::fabs(ya - yb) > 1e-6 * std::max(1.0, std::fabs(ya));
      continue;
    }
    double z = std::fabs(ya - yb) / std::sqrt(var);
    over += z > 3.29;
    if (z > worst) worst = z, worst_pixel = i;
  }
  double bound = n * 0.001 + 5.0 * std::sqrt(n * 0.001);
  double z_image = stouffer_z(a, b);
  EXPECT_LE(double(over), bound) << what << ": " << over << " of " << n << " pixels beyond |z| = 3.29";
  EXPECT_LT(worst, 6.5) << what << ": pixel (" << worst_pixel % a.width << "," << worst_pixel / a.width
                        << ") differs by |z| = " << worst;
  EXPECT_EQ(noiseless_mismatch, 0u) << what << ": noiseless pixels differ";
  EXPECT_LT(std::fabs(z_image), 5.0) << what << ": image means differ, Stouffer Z = " << z_image;
  std::printf(
      "  %s: Stouffer Z %.2f (detects a %.2g%% bias with probability 0.95), %zu/%zu pixels beyond |z| = 3.29 (bound "
      "%.1f), max |z| %.2f\n",
      what.c_str(), z_image, 100.0 * stouffer_detectable_bias(a, b), over, n, bound, worst);
}

Film scaled_film(const Film& film, float factor) {
  Film f = film;
  for (float3& c : f.radiance) c *= factor;
  return f;
}

}  // namespace pt::test
