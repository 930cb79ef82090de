// Row-major 4x4 matrix for composing COLLADA node transforms while loading.
// Rendering never sees a matrix: the loader bakes transforms into world space.
#pragma once

#include <array>
#include <cmath>
#include <numbers>

#include "kernels/math/vec3.h"

namespace pt {

/// 64 bytes, row-major: m[row][col]; points are column vectors (p' = M p).
struct Mat4 {
  std::array<std::array<float, 4>, 4> m{};

  static Mat4 identity() {
    Mat4 r;
    for (int i = 0; i < 4; ++i) r.m[i][i] = 1.0f;
    return r;
  }
  static Mat4 translation(float3 t) {
    Mat4 r = identity();
    for (int i = 0; i < 3; ++i) r.m[i][3] = t[i];
    return r;
  }
  static Mat4 scaling(float3 s) {
    Mat4 r = identity();
    for (int i = 0; i < 3; ++i) r.m[i][i] = s[i];
    return r;
  }
  /// Rotation by `degrees` about `axis` (need not be unit; zero axis -> identity).
  static Mat4 rotation(float3 axis, float degrees) {
    float len = length(axis);
    if (!(len > 0.0f)) return identity();
    float3 a = axis / len;
    float rad = degrees * std::numbers::pi_v<float> / 180.0f;
    float c = std::cos(rad), s = std::sin(rad), k = 1.0f - c;
    Mat4 r = identity();
    r.m[0] = {a.x * a.x * k + c, a.x * a.y * k - a.z * s, a.x * a.z * k + a.y * s, 0};
    r.m[1] = {a.y * a.x * k + a.z * s, a.y * a.y * k + c, a.y * a.z * k - a.x * s, 0};
    r.m[2] = {a.z * a.x * k - a.y * s, a.z * a.y * k + a.x * s, a.z * a.z * k + c, 0};
    return r;
  }

  /// Affine: the bottom row is ignored (COLLADA node transforms are affine).
  float3 transform_point(float3 p) const { return transform_vector(p) + float3{m[0][3], m[1][3], m[2][3]}; }
  float3 transform_vector(float3 v) const {
    return {m[0][0] * v.x + m[0][1] * v.y + m[0][2] * v.z, m[1][0] * v.x + m[1][1] * v.y + m[1][2] * v.z,
            m[2][0] * v.x + m[2][1] * v.y + m[2][2] * v.z};
  }
  bool is_finite() const {
    for (const auto& row : m)
      for (float v : row)
        if (!std::isfinite(v)) return false;
    return true;
  }
};
static_assert(sizeof(Mat4) == 64);

inline Mat4 operator*(const Mat4& a, const Mat4& b) {
  Mat4 r;
  for (int i = 0; i < 4; ++i)
    for (int j = 0; j < 4; ++j) {
      float s = 0.0f;
      for (int k = 0; k < 4; ++k) s += a.m[i][k] * b.m[k][j];
      r.m[i][j] = s;
    }
  return r;
}

}  // namespace pt
