// The render's own error estimate (error_estimate.h).
#include "kernels/render/error_estimate.h"

#include <algorithm>
#include <bit>
#include <cmath>

namespace pt {
namespace {

constexpr int kBlock = 8;

double squared_change(const float (&a)[3], const float (&b)[3]) {
  double s = 0.0;
  for (int c = 0; c < 3; ++c) {
    const double d = double(a[c]) - double(b[c]);
    s += d * d;
  }
  return s / 3.0;
}

/// The ratio r = D(P) / D(P/2) of the accumulated pixels: the median over the
/// image's 8x8 blocks (aligned to the image's origin, clipped to the area) of
/// each block's ratio of sums, over the blocks where both sums are positive.
/// A median, not the ratio of the image's sums: a few pixels whose path found
/// a rare bright light (early in one render, late in another) swing the sums'
/// ratio far from the rest of the image's decay. 0.5, the ratio of independent
/// samples, when no block has both.
double image_step_ratio(const Accumulation& acc, const std::vector<StepChanges>& steps) {
  const Region& a = acc.area;
  std::vector<double> ratios;
  for (int by = a.y / kBlock * kBlock; by < a.y + a.height; by += kBlock)
    for (int bx = a.x / kBlock * kBlock; bx < a.x + a.width; bx += kBlock) {
      double half = 0.0, quarter = 0.0;
      for (int y = std::max(by, a.y); y < std::min(by + kBlock, a.y + a.height); ++y)
        for (int x = std::max(bx, a.x); x < std::min(bx + kBlock, a.x + a.width); ++x) {
          const StepChanges& s = steps[size_t(y - a.y) * a.width + (x - a.x)];
          half += s.half;
          quarter += s.quarter;
        }
      if (half > 0.0 && quarter > 0.0) ratios.push_back(half / quarter);
    }
  if (ratios.empty()) return 0.5;
  const size_t mid = ratios.size() / 2;
  std::nth_element(ratios.begin(), ratios.begin() + long(mid), ratios.end());
  double median = ratios[mid];
  if (ratios.size() % 2 == 0) median = 0.5 * (median + *std::max_element(ratios.begin(), ratios.begin() + long(mid)));
  return median;
}

std::vector<StepChanges> all_step_changes(const Accumulation& acc) {
  std::vector<StepChanges> steps(acc.pixels.size());
  for (size_t i = 0; i < steps.size(); ++i) steps[i] = step_changes(acc.pixels[i]);
  return steps;
}

}  // namespace

StepChanges step_changes(const PixelAccumulator& p) {
  if (p.samples < 4) return {};
  return {squared_change(p.at_powers[1], p.at_powers[0]), squared_change(p.at_powers[2], p.at_powers[1])};
}

double remaining_error_factor(double ratio) {
  const double r = std::clamp(ratio, kMinStepRatio, kMaxStepRatio);
  return r / (1.0 - r);
}

ImageErrorEstimate estimate_image_error(const Accumulation& acc, double scale) {
  ImageErrorEstimate e;
  if (acc.pixels.empty()) return e;
  uint32_t fewest = UINT32_MAX;
  double value = 0.0;
  for (const PixelAccumulator& p : acc.pixels) {
    fewest = std::min(fewest, p.samples);
    const float3 m = p.mean();
    value += (double(m.x) + m.y + m.z) / 3.0;
  }
  if (fewest < 4) return e;
  const std::vector<StepChanges> steps = all_step_changes(acc);
  double half = 0.0;
  for (const StepChanges& s : steps) half += s.half;
  const double n = double(acc.pixels.size());
  e.step_ratio = std::clamp(image_step_ratio(acc, steps), kMinStepRatio, kMaxStepRatio);
  e.available = true;
  e.rmse = scale * std::sqrt(half / n * remaining_error_factor(e.step_ratio));
  e.relative_rmse = value > 0.0 ? e.rmse / (value / n) : 0.0;
  e.at_samples = std::bit_floor(fewest);
  return e;
}

std::vector<float> estimate_pixel_error(const Accumulation& acc) {
  const std::vector<StepChanges> steps = all_step_changes(acc);
  const double factor = remaining_error_factor(image_step_ratio(acc, steps));
  std::vector<float> out(steps.size());
  for (size_t i = 0; i < steps.size(); ++i) out[i] = static_cast<float>(std::sqrt(steps[i].half * factor));
  return out;
}

}  // namespace pt
