// EnvironmentMap: the lat-long mapping, the course's bilinear lookup, and the
// piecewise-constant sampling distribution (built once, in double, stored as
// float CDFs whose differences are the texel probabilities).
#include "kernels/scene/environment_map.h"

#include <algorithm>
#include <cassert>
#include <cfloat>
#include <cmath>
#include <numbers>

#include "kernels/math/sampling.h"

namespace pt {
namespace {

constexpr float kOneMinusEpsilon = 0x1.fffffep-1f;

float clamp_unit(float u) {
  if (!(u >= 0.0f)) return 0.0f;  // also NaN
  return std::min(u, kOneMinusEpsilon);
}

/// Luminance as a sampling weight: >= 0 and finite.
float weight_of(const float3& rgb) {
  float l = illuminance(rgb);
  return std::isfinite(l) && l > 0.0f ? l : 0.0f;
}

/// Largest weight over each texel and its 8 neighbours (x wraps, y clamps):
/// the texels the bilinear lookup inside texel (i, j) can read.
std::vector<float> dilated_weights(int w, int h, const std::vector<float3>& texels) {
  std::vector<float> row_max(size_t(w) * h), out(size_t(w) * h);
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const size_t r = size_t(j) * w;
      const float l = weight_of(texels[r + (i + w - 1) % w]), c = weight_of(texels[r + i]),
                  rr = weight_of(texels[r + (i + 1) % w]);
      row_max[r + i] = std::max(l, std::max(c, rr));
    }
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const float up = row_max[size_t(std::max(j - 1, 0)) * w + i];
      const float down = row_max[size_t(std::min(j + 1, h - 1)) * w + i];
      out[size_t(j) * w + i] = std::max(row_max[size_t(j) * w + i], std::max(up, down));
    }
  return out;
}

/// cdf[0..n] from n non-negative weights: prefix sums / total, cdf[n] = 1
/// exactly; uniform when the total is 0. Returns the total.
double fill_cdf(const double* weights, int n, float* cdf) {
  double total = 0.0;
  for (int k = 0; k < n; ++k) total += weights[k];
  double prefix = 0.0;
  cdf[0] = 0.0f;
  for (int k = 1; k < n; ++k) {
    prefix += weights[k - 1];
    cdf[k] = total > 0.0 ? static_cast<float>(prefix / total) : static_cast<float>(double(k) / n);
  }
  cdf[n] = 1.0f;
  return total;
}

/// Index k in [0, n) with cdf[k] <= u < cdf[k + 1] (u in [0, 1), cdf[n] = 1):
/// never an entry of zero probability.
int find_interval(const float* cdf, int n, float u) {
  int k = static_cast<int>(std::upper_bound(cdf, cdf + n, u) - cdf) - 1;
  return std::clamp(k, 0, n - 1);
}

/// Position in [k, k + 1) of u within [cdf[k], cdf[k + 1]).
float offset_in(const float* cdf, int k, float u) {
  const float width = cdf[k + 1] - cdf[k];
  float t = width > 0.0f ? (u - cdf[k]) / width : 0.5f;
  t = std::clamp(t, 0.0f, kOneMinusEpsilon);
  const float p = static_cast<float>(k) + t;
  return p < static_cast<float>(k + 1) ? p : std::nextafter(static_cast<float>(k + 1), 0.0f);
}

}  // namespace

EnvironmentMap::EnvironmentMap(int width, int height, std::vector<float3> texels)
    : width_(width), height_(height), texels_(std::move(texels)) {
  assert(width_ >= 1 && height_ >= 1 && texels_.size() == size_t(width_) * height_);
  std::vector<float> weight = dilated_weights(width_, height_, texels_);
  if (std::all_of(weight.begin(), weight.end(), [](float v) { return v == 0.0f; }))
    std::fill(weight.begin(), weight.end(), 1.0f);

  marginal_cdf_.resize(size_t(height_) + 1);
  conditional_cdf_.resize(size_t(height_) * (width_ + 1));
  std::vector<double> row(width_), row_total(height_);
  for (int j = 0; j < height_; ++j) {
    const double sin_theta = std::sin(std::numbers::pi * (j + 0.5) / height_);
    for (int i = 0; i < width_; ++i) row[i] = double(weight[size_t(j) * width_ + i]) * sin_theta;
    row_total[j] = fill_cdf(row.data(), width_, &conditional_cdf_[size_t(j) * (width_ + 1)]);
  }
  fill_cdf(row_total.data(), height_, marginal_cdf_.data());
}

bool EnvironmentMap::image_coordinates(const float3& dir, float& x, float& y, float& sin_theta) const {
  const float r = std::sqrt(dir.x * dir.x + dir.z * dir.z);
  const float len = std::sqrt(r * r + dir.y * dir.y);
  if (!(len > 0.0f) || !std::isfinite(len)) return false;
  const float theta = std::atan2(r, dir.y);           // [0, pi]
  const float phi = std::atan2(-dir.z, dir.x) + kPi;  // [0, 2 pi]
  x = std::clamp(phi * (kInv2Pi * width_), 0.0f, float(width_));
  y = std::clamp(theta * (kInvPi * height_), 0.0f, float(height_));
  sin_theta = r / len;
  return true;
}

float3 EnvironmentMap::direction(float x, float y) const {
  const float theta = y * (kPi / height_), phi = x * (2.0f * kPi / width_);
  const float st = std::sin(theta);
  return {-st * std::cos(phi), std::cos(theta), st * std::sin(phi)};
}

float3 EnvironmentMap::lookup(float x, float y) const {
  if (!std::isfinite(x) || !std::isfinite(y)) return {};
  x = std::clamp(x, 0.0f, float(width_));
  y = std::clamp(y, 0.0f, float(height_));
  // Columns: the centres left and right of x, wrapping.
  const int right_raw = static_cast<int>(std::lround(x));
  const float dx = x - static_cast<float>(right_raw) + 0.5f;
  const int right = right_raw % width_, left = (right_raw + width_ - 1) % width_;
  // Rows: the centres above and below y, clamped.
  const int below_raw = static_cast<int>(std::lround(y));
  const float dy = y - static_cast<float>(below_raw) + 0.5f;
  const int above = std::max(below_raw - 1, 0), below = std::min(below_raw, height_ - 1);
  const float3 top = texel(left, above) * (1.0f - dx) + texel(right, above) * dx;
  const float3 bottom = texel(left, below) * (1.0f - dx) + texel(right, below) * dx;
  return top * (1.0f - dy) + bottom * dy;
}

float3 EnvironmentMap::radiance(const float3& dir) const {
  float x, y, sin_theta;
  if (!image_coordinates(dir, x, y, sin_theta)) return {};
  return lookup(x, y);
}

float EnvironmentMap::texel_probability(int i, int j) const {
  const float* c = &conditional_cdf_[size_t(j) * (width_ + 1)];
  return (marginal_cdf_[j + 1] - marginal_cdf_[j]) * (c[i + 1] - c[i]);
}

float EnvironmentMap::pdf(const float3& dir) const {
  float x, y, sin_theta;
  if (!image_coordinates(dir, x, y, sin_theta) || !(sin_theta > 0.0f)) return 0.0f;
  const int i = std::min(static_cast<int>(x), width_ - 1), j = std::min(static_cast<int>(y), height_ - 1);
  const double p =
      double(texel_probability(i, j)) * width_ * height_ / (2.0 * std::numbers::pi * std::numbers::pi * sin_theta);
  return static_cast<float>(std::min(p, double(FLT_MAX)));
}

EnvironmentMap::Sample EnvironmentMap::sample(float u1, float u2) const {
  u1 = clamp_unit(u1);
  u2 = clamp_unit(u2);
  // Row from the marginal, column from that row's conditional, point uniform in the texel.
  const int j = find_interval(marginal_cdf_.data(), height_, u1);
  const float y = offset_in(marginal_cdf_.data(), j, u1);
  const float* c = &conditional_cdf_[size_t(j) * (width_ + 1)];
  const int i = find_interval(c, width_, u2);
  const float x = offset_in(c, i, u2);
  Sample s;
  s.wi = direction(x, y);
  s.pdf = pdf(s.wi);
  s.radiance = radiance(s.wi);
  return s;
}

}  // namespace pt
