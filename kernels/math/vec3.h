// float3: the three-component float vector used for points, directions and RGB
// radiance everywhere in the renderer, with the handful of operations shading and
// geometry need. Single precision by design; doubles appear only in accumulators.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"

namespace pt {

/// 12 bytes: x, y, z. Also used as linear RGB.
struct float3 {
  float x = 0, y = 0, z = 0;

  constexpr float3() = default;
  constexpr float3(float x_, float y_, float z_) : x(x_), y(y_), z(z_) {}
  constexpr explicit float3(float s) : x(s), y(s), z(s) {}

  constexpr float operator[](int i) const { return i == 0 ? x : (i == 1 ? y : z); }
  constexpr float& operator[](int i) { return i == 0 ? x : (i == 1 ? y : z); }

  constexpr float3& operator+=(float3 b) {
    x += b.x;
    y += b.y;
    z += b.z;
    return *this;
  }
  constexpr float3& operator-=(float3 b) {
    x -= b.x;
    y -= b.y;
    z -= b.z;
    return *this;
  }
  constexpr float3& operator*=(float3 b) {
    x *= b.x;
    y *= b.y;
    z *= b.z;
    return *this;
  }
  constexpr float3& operator*=(float s) {
    x *= s;
    y *= s;
    z *= s;
    return *this;
  }
  constexpr float3& operator/=(float s) { return *this *= (1.0f / s); }
};
static_assert(sizeof(float3) == 12);

inline namespace PT_ISA_NS {
constexpr float3 operator+(float3 a, float3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
constexpr float3 operator-(float3 a, float3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
constexpr float3 operator-(float3 a) { return {-a.x, -a.y, -a.z}; }
constexpr float3 operator*(float3 a, float3 b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
constexpr float3 operator*(float3 a, float s) { return {a.x * s, a.y * s, a.z * s}; }
constexpr float3 operator*(float s, float3 a) { return a * s; }
constexpr float3 operator/(float3 a, float s) { return a * (1.0f / s); }
constexpr bool operator==(float3 a, float3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

constexpr float dot(float3 a, float3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
constexpr float3 cross(float3 a, float3 b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline float length(float3 a) { return std::sqrt(dot(a, a)); }
inline float3 normalize(float3 a) { return a / length(a); }
inline float3 min(float3 a, float3 b) { return {std::min(a.x, b.x), std::min(a.y, b.y), std::min(a.z, b.z)}; }
inline float3 max(float3 a, float3 b) { return {std::max(a.x, b.x), std::max(a.y, b.y), std::max(a.z, b.z)}; }
inline float3 abs(float3 a) { return {std::fabs(a.x), std::fabs(a.y), std::fabs(a.z)}; }
constexpr float max_component(float3 a) { return std::max(a.x, std::max(a.y, a.z)); }
inline bool is_finite(float3 a) { return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z); }
constexpr bool is_black(float3 a) { return a.x == 0 && a.y == 0 && a.z == 0; }

/// Index (0, 1, 2) of the largest component.
constexpr int max_axis(float3 a) { return a.x >= a.y ? (a.x >= a.z ? 0 : 2) : (a.y >= a.z ? 1 : 2); }

/// Photometric illuminance of a linear RGB value (Rec. 709 weights), as CS184 uses it.
constexpr float illuminance(float3 rgb) { return 0.2126f * rgb.x + 0.7152f * rgb.y + 0.0722f * rgb.z; }

}  // namespace PT_ISA_NS
}  // namespace pt
