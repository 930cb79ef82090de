// Ray and hit records for single-ray tracing. Rays (input) and hits (output) are
// separate, as in Embree: an occlusion query reads a Ray and answers yes or no.
#pragma once

#include <cstdint>
#include <limits>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/vec3.h"

namespace pt {

inline constexpr float kInfinity = std::numeric_limits<float>::infinity();
inline constexpr uint32_t kInvalidId = 0xFFFFFFFFu;

/// 32 bytes: origin, tmin, direction, tmax. Directions need not be normalised;
/// t is measured in units of the direction's length.
struct Ray {
  float3 org;
  float tmin = 0.0f;
  float3 dir;
  float tmax = kInfinity;
};
static_assert(sizeof(Ray) == 32);

/// Which kind of primitive a hit refers to. Triangle ids and sphere ids are
/// separate index spaces of the scene.
enum class PrimKind : uint32_t { kTriangle = 0, kSphere = 1 };

/// 16 bytes: distance and barycentrics (u weights vertex 1, v weights vertex 2)
/// plus the primitive id whose top bit says sphere (1) or triangle (0).
/// A miss has prim == kInvalidId and t == the ray's tmax.
struct Hit {
  float t = kInfinity;
  float u = 0.0f, v = 0.0f;
  uint32_t prim = kInvalidId;

  static constexpr uint32_t kSphereBit = 0x80000000u;
  bool valid() const { return prim != kInvalidId; }
  bool is_sphere() const { return valid() && (prim & kSphereBit) != 0; }
  uint32_t index() const { return prim & ~kSphereBit; }
};
static_assert(sizeof(Hit) == 16);

inline namespace PT_ISA_NS {
inline uint32_t sphere_prim_id(uint32_t sphere_index) { return sphere_index | Hit::kSphereBit; }

}  // namespace PT_ISA_NS
}  // namespace pt
