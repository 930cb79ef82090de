// The environment light: a lat-long HDR image around the scene, read the way
// the course renderer reads it (docs/rendering.md), looked up
// bilinearly, and importance-sampled by a 2-D piecewise-constant distribution
// over its texels (marginal over rows, conditional within each row). The
// texels come from the caller (io/exr_image.h reads them); nothing here
// reads files or throws.
#pragma once

#include <cstddef>
#include <vector>

#include "kernels/math/vec3.h"

namespace pt {

/// Memory: 12 bytes per texel (the RGB image) + 4 bytes per conditional CDF
/// entry (height * (width + 1)) + 4 bytes per marginal CDF entry
/// (height + 1): about 16 bytes per texel.
///
/// Mapping: unit direction d (Y up) -> theta = acos(d.y) in [0, pi],
/// phi = atan2(-d.z, d.x) + pi in [0, 2 pi]; image coordinates
/// x = phi / (2 pi) * width, y = theta / pi * height (row 0 is straight up,
/// texel (i, j) covers [i, i+1) x [j, j+1), its centre is (i + 0.5, j + 0.5)).
class EnvironmentMap {
 public:
  /// 28 bytes. A sampled direction leaving the scene, its solid-angle pdf
  /// and the radiance arriving along it (radiance(wi)). pdf == 0 (only on
  /// the poles, where sin(theta) == 0) means: discard the sample.
  struct Sample {
    float3 wi;
    float pdf = 0.0f;
    float3 radiance;
  };

  /// `texels`: width * height linear RGB values, row 0 first, each finite
  /// and >= 0 (what read_exr guarantees); width, height >= 1. Builds the
  /// sampling distribution: texel (i, j) weighs the largest luminance over
  /// it and its 8 neighbours (wrapping in x, clamped in y) times
  /// sin(theta at the row centre), so that every texel where the bilinear
  /// lookup can be non-zero has a positive probability. An all-black map
  /// weighs every texel by sin(theta) alone.
  EnvironmentMap(int width, int height, std::vector<float3> texels);

  int width() const { return width_; }
  /// Bytes held: texels and both CDFs.
  size_t bytes() const {
    return texels_.capacity() * sizeof(float3) +
           (marginal_cdf_.capacity() + conditional_cdf_.capacity()) * sizeof(float);
  }
  int height() const { return height_; }

  /// Bilinear radiance along unit direction `dir` leaving the scene (the
  /// course's bilerp: texel centres at (i + 0.5, j + 0.5), wrapping in x,
  /// clamped in y). Black for a non-finite direction.
  float3 radiance(const float3& dir) const;

  /// The same lookup at continuous image coordinates, x in [0, width],
  /// y in [0, height]; exactly texel (i, j) at (i + 0.5, j + 0.5).
  float3 lookup(float x, float y) const;

  /// Importance sample for u1, u2 in [0, 1) (values outside are clamped):
  /// a texel with its probability, then a point uniform in (x, y) within it.
  /// Guarantees: finite wi of unit length, pdf == pdf(wi) bit for bit,
  /// radiance == radiance(wi), never NaN.
  Sample sample(float u1, float u2) const;

  /// Solid-angle pdf with which sample() returns dir:
  /// p(texel) * width * height / (2 pi^2 sin(theta)), where p(texel) is
  /// the texel's probability under the stored (float) CDFs, i.e. exactly the
  /// measure of the u that select it. 0 where sin(theta) == 0 and for a
  /// non-finite dir.
  float pdf(const float3& dir) const;

  /// Image coordinates of a direction (need not be unit), and sin(theta).
  /// Returns false for a zero or non-finite direction.
  bool image_coordinates(const float3& dir, float& x, float& y, float& sin_theta) const;

  /// The unit direction at image coordinates (x, y).
  float3 direction(float x, float y) const;

 private:
  const float3& texel(int i, int j) const { return texels_[size_t(j) * width_ + i]; }
  /// Probability of texel (i, j): marginal(j) * conditional(i | j).
  float texel_probability(int i, int j) const;

  int width_, height_;
  std::vector<float3> texels_;          ///< width * height, row 0 first
  std::vector<float> marginal_cdf_;     ///< height + 1 entries, 0 ... 1
  std::vector<float> conditional_cdf_;  ///< height rows of width + 1 entries, 0 ... 1
};
static_assert(sizeof(EnvironmentMap::Sample) == 28);

}  // namespace pt
