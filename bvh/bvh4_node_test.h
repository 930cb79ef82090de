// The 4-wide slab test of one Bvh4Node against one ray, with the per-ray
// constants computed once: reciprocal direction (tiny components clamped, so
// no 0 * inf NaN), origin times reciprocal (one fused multiply-subtract per
// plane where the CPU has FMA: the build turns off implicit contraction), and
// the byte offsets of the near and far planes per axis (no branch on
// direction signs).
#pragma once

#include <cmath>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "bvh4.h"
#include "kernels/math/ray.h"
#include "kernels/simd/simd.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Whether the query is well-formed: finite origin and direction, tmin and
/// tmax not NaN. Other rays hit nothing.
PT_ALWAYS_INLINE bool ray_is_traceable(const Ray& r) {
  return is_finite(r.org) && is_finite(r.dir) && !std::isnan(r.tmin) && !std::isnan(r.tmax) && r.tmin < r.tmax;
}

/// Per-ray constants of the node test.
struct NodeRay {
  vfloat4 rdir[3];      ///< 1 / dir, components of |dir| < kMinDir clamped to +-kMinDir first
  vfloat4 org_rdir[3];  ///< org * rdir
  uint32_t near[3];     ///< byte offset of the near plane row per axis
  uint32_t far[3];      ///< byte offset of the far plane row per axis

  static constexpr float kMinDir = 1e-18f;

  /// 1 / d, |d| < kMinDir clamped to +-kMinDir first.
  PT_ALWAYS_INLINE static float reciprocal(float d) {
    const float safe = std::fabs(d) < kMinDir ? std::copysign(kMinDir, d) : d;
    return 1.0f / safe;
  }

  NodeRay() = default;
  PT_ALWAYS_INLINE explicit NodeRay(const Ray& r) {
    for (int a = 0; a < 3; ++a) {
      const float inv = reciprocal(r.dir[a]);
      rdir[a] = vfloat4(inv);
      org_rdir[a] = vfloat4(r.org[a] * inv);
      uint32_t lower = uint32_t(2 * a * sizeof(float[4])), upper = lower + uint32_t(sizeof(float[4]));
      near[a] = inv >= 0.0f ? lower : upper;
      far[a] = inv >= 0.0f ? upper : lower;
    }
  }
};

/// The four children's near and far planes of each axis, for rays whose
/// near and far planes lie at byte offsets near[a] and far[a] of the node
/// (NodeRay's).
struct ChildPlanes {
  vfloat4 near[3], far[3];
};
PT_ALWAYS_INLINE ChildPlanes child_planes(const Bvh4Node& node, const uint32_t (&near)[3], const uint32_t (&far)[3]) {
  const char* base = reinterpret_cast<const char*>(&node);
  auto plane = [base](uint32_t offset) { return vfloat4::load_aligned(reinterpret_cast<const float*>(base + offset)); };
  return {{plane(near[0]), plane(near[1]), plane(near[2])}, {plane(far[0]), plane(far[1]), plane(far[2])}};
}

/// Slab test of the four children whose planes are `p` against the ray of
/// constants rdir and org_rdir (NodeRay's) over [tmin, tmax]: the children
/// it enters, and their entry distances in `tnear`.
PT_ALWAYS_INLINE vbool4 children_entered(const ChildPlanes& p, const vfloat4 (&rdir)[3], const vfloat4 (&org_rdir)[3],
                                         const vfloat4& tmin, const vfloat4& tmax, vfloat4& tnear) {
  const vfloat4 tnx = fused_mul_sub(p.near[0], rdir[0], org_rdir[0]);
  const vfloat4 tny = fused_mul_sub(p.near[1], rdir[1], org_rdir[1]);
  const vfloat4 tnz = fused_mul_sub(p.near[2], rdir[2], org_rdir[2]);
  const vfloat4 tfx = fused_mul_sub(p.far[0], rdir[0], org_rdir[0]);
  const vfloat4 tfy = fused_mul_sub(p.far[1], rdir[1], org_rdir[1]);
  const vfloat4 tfz = fused_mul_sub(p.far[2], rdir[2], org_rdir[2]);
  tnear = xsimd::max(xsimd::max(tnx, tny), xsimd::max(tnz, tmin));
  const vfloat4 tfar = xsimd::min(xsimd::min(tfx, tfy), xsimd::min(tfz, tmax));
  return tnear <= tfar;
}

/// Slab test of the four children of `node` over [tmin, tmax]. Returns the
/// bit mask of children hit and their entry distances in `tnear`.
PT_ALWAYS_INLINE uint32_t intersect_node(const Bvh4Node& node, const NodeRay& r, const vfloat4& tmin,
                                         const vfloat4& tmax, vfloat4& tnear) {
  return movemask(children_entered(child_planes(node, r.near, r.far), r.rdir, r.org_rdir, tmin, tmax, tnear));
}

/// The near and far plane rows (0-5, as intersect_node takes them) of each
/// axis for rays of one direction octant: bit a of `octant` set where the
/// reciprocal direction on axis a is negative.
struct OctantPlanes {
  uint32_t near[3], far[3];
  OctantPlanes() : OctantPlanes(0) {}
  explicit OctantPlanes(uint32_t octant) {
    for (uint32_t a = 0; a < 3; ++a) {
      const bool negative = (octant >> a & 1) != 0;
      near[a] = 2 * a + (negative ? 1 : 0);
      far[a] = 2 * a + (negative ? 0 : 1);
    }
  }
  /// The rows as byte offsets in a node (NodeRay's near and far).
  void offsets(uint32_t (&near_offset)[3], uint32_t (&far_offset)[3]) const {
    for (int a = 0; a < 3; ++a)
      near_offset[a] = near[a] * uint32_t(sizeof(float[4])), far_offset[a] = far[a] * uint32_t(sizeof(float[4]));
  }
};

/// The octant of a ray: bit a set when NodeRay's reciprocal direction on
/// axis a is negative (the sign bit of dir[a], -0 included: NodeRay clamps it
/// to -kMinDir). Under flush-to-zero a component below -8.5e37 has a
/// reciprocal of -0, which NodeRay counts as positive; then both planes give
/// the same distances (0 times either), so the test's answer is the same.
PT_ALWAYS_INLINE uint32_t octant_of(const Ray& r) {
  return uint32_t(std::signbit(r.dir.x)) | uint32_t(std::signbit(r.dir.y)) << 1 | uint32_t(std::signbit(r.dir.z)) << 2;
}

#if PT_PER_LEVEL
/// K rays' slab constants (NodeRay's, lane by lane) and their [tmin, tmax].
struct NodeLanes {
  vfloatK rdir[3], org_rdir[3], tmin, tmax;
};

/// Which of K rays enter child c of `node`, and their entry distances in
/// `tnear`: each axis's two planes ordered lane by lane (rays of any
/// directions).
PT_ALWAYS_INLINE vboolK lanes_enter_child(const Bvh4Node& node, int c, const NodeLanes& r, vfloatK& tnear) {
  vfloatK tn = r.tmin, tf = r.tmax;
  for (int a = 0; a < 3; ++a) {
    const vfloatK t0 = fused_mul_sub_k(vfloatK(node.bounds[2 * a][c]), r.rdir[a], r.org_rdir[a]);
    const vfloatK t1 = fused_mul_sub_k(vfloatK(node.bounds[2 * a + 1][c]), r.rdir[a], r.org_rdir[a]);
    tn = xsimd::max(tn, xsimd::min(t0, t1));
    tf = xsimd::min(tf, xsimd::max(t0, t1));
  }
  tnear = tn;
  return tn <= tf;
}

/// lanes_enter_child for K rays of one direction octant: each axis's near and
/// far plane as intersect_node takes them, which need no min and max.
PT_ALWAYS_INLINE vboolK lanes_enter_child(const Bvh4Node& node, int c, const NodeLanes& r, const OctantPlanes& p,
                                          vfloatK& tnear) {
  auto plane = [&](uint32_t row, int a) {
    return fused_mul_sub_k(vfloatK(node.bounds[row][c]), r.rdir[a], r.org_rdir[a]);
  };
  tnear = xsimd::max(xsimd::max(plane(p.near[0], 0), plane(p.near[1], 1)), xsimd::max(plane(p.near[2], 2), r.tmin));
  const vfloatK tfar =
      xsimd::min(xsimd::min(plane(p.far[0], 0), plane(p.far[1], 1)), xsimd::min(plane(p.far[2], 2), r.tmax));
  return tnear <= tfar;
}

/// NodeRay's constants of K rays: the reciprocal direction (tiny components
/// clamped, as NodeRay clamps them) and the origin times it.
PT_ALWAYS_INLINE void slab_constants(const vfloatK (&org)[3], const vfloatK (&dir)[3], vfloatK (&rdir)[3],
                                     vfloatK (&org_rdir)[3]) {
  const vfloatK min_dir(NodeRay::kMinDir);
  for (int a = 0; a < 3; ++a) {
    const vfloatK safe = xsimd::select(xsimd::abs(dir[a]) < min_dir, xsimd::copysign(min_dir, dir[a]), dir[a]);
    rdir[a] = vfloatK(1.0f) / safe;
    org_rdir[a] = org[a] * rdir[a];
  }
}

/// The lanes of K rays that are traceable (ray_is_traceable's test).
PT_ALWAYS_INLINE vboolK lanes_traceable(const vfloatK (&org)[3], const vfloatK (&dir)[3], const vfloatK& tmin,
                                        const vfloatK& tmax) {
  vboolK ok = tmin < tmax;  // false for NaN
  for (int a = 0; a < 3; ++a) ok = ok & xsimd::isfinite(org[a]) & xsimd::isfinite(dir[a]);
  return ok;
}
#endif

}  // namespace PT_ISA_NS
}  // namespace pt
