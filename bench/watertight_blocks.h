// The watertight ray-triangle test of Woop, Benthin and Wald (2013) on the
// 4-wide BVH's blocks, for the benchmark and the tests: blocks rewritten with
// rows v0, v1, v2 (to_watertight) and the block test the walks take as their
// leaf test (WatertightBlocks, bvh/bvh4_leaf_test.h's shape). The renderer's
// leaves are Moller-Trumbore's; this is the form to measure it against.
#pragma once

#include <cstdint>
#include <span>
#include <utility>

#include "bvh/bvh4.h"
#include "bvh/triangle4_intersect.h"
#include "kernels/math/ray.h"
#include "kernels/scene/scene.h"
#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/simd.h"

namespace pt::bench {

/// The same tree with every block's rows v0, v1, v2 of its triangles (the
/// scene's own vertices, so that two triangles that share an edge share it
/// bit for bit); padding lanes stay degenerate.
Bvh4 to_watertight(const Bvh4& bvh, std::span<const float3> positions, std::span<const TriangleIndices> triangles);

inline namespace PT_ISA_NS {

/// Per-ray constants of the watertight test: the dominant direction axis
/// becomes z (kz), the shear maps the direction onto +z.
struct WatertightBlockRay {
  uint32_t kx, ky, kz;
  vfloat4 org[3];  ///< origin in permuted order (x = org[kx], ...)
  vfloat4 sx, sy, sz, tmin;
  WatertightBlockRay() = default;
  explicit WatertightBlockRay(const Ray& r) : tmin(r.tmin) {
    const float3 a = abs(r.dir);
    kz = static_cast<uint32_t>(max_axis(a));
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (r.dir[kz] < 0.0f) std::swap(kx, ky);  // keep the winding
    sx = vfloat4(r.dir[kx] / r.dir[kz]);
    sy = vfloat4(r.dir[ky] / r.dir[kz]);
    sz = vfloat4(1.0f / r.dir[kz]);
    org[0] = vfloat4(r.org[kx]);
    org[1] = vfloat4(r.org[ky]);
    org[2] = vfloat4(r.org[kz]);
  }
};

/// Recomputes the edge functions of the lanes where one is exactly zero in
/// double precision (products of floats are exact there), as Woop et al. do.
inline void watertight_edges_in_double(const float ax[4], const float ay[4], const float bx[4], const float by[4],
                                       const float cx[4], const float cy[4], uint32_t lanes, vfloat4& u, vfloat4& v,
                                       vfloat4& w) {
  alignas(16) float fu[4], fv[4], fw[4];
  u.store_aligned(fu);
  v.store_aligned(fv);
  w.store_aligned(fw);
  for (int i = 0; i < 4; ++i) {
    if (!(lanes >> i & 1)) continue;
    fu[i] = static_cast<float>(double(cx[i]) * by[i] - double(cy[i]) * bx[i]);
    fv[i] = static_cast<float>(double(ax[i]) * cy[i] - double(ay[i]) * cx[i]);
    fw[i] = static_cast<float>(double(bx[i]) * ay[i] - double(by[i]) * ax[i]);
  }
  u = vfloat4::load_aligned(fu);
  v = vfloat4::load_aligned(fv);
  w = vfloat4::load_aligned(fw);
}

/// Watertight test on a block whose rows are v0, v1, v2 (to_watertight).
PT_ALWAYS_INLINE uint32_t intersect_block_watertight(const TriangleBlock4& b, const WatertightBlockRay& r,
                                                     const vfloat4& tmax, BlockHits& h) {
  auto row = [](const float(*rows)[4], uint32_t axis) { return vfloat4::load_aligned(rows[axis]); };
  vfloat4 az = row(b.v0, r.kz) - r.org[2], bz = row(b.r1, r.kz) - r.org[2], cz = row(b.r2, r.kz) - r.org[2];
  vfloat4 ax = (row(b.v0, r.kx) - r.org[0]) - r.sx * az, ay = (row(b.v0, r.ky) - r.org[1]) - r.sy * az;
  vfloat4 bx = (row(b.r1, r.kx) - r.org[0]) - r.sx * bz, by = (row(b.r1, r.ky) - r.org[1]) - r.sy * bz;
  vfloat4 cx = (row(b.r2, r.kx) - r.org[0]) - r.sx * cz, cy = (row(b.r2, r.ky) - r.org[1]) - r.sy * cz;
  vfloat4 u = keep_rounded(cx * by) - keep_rounded(cy * bx);
  vfloat4 v = keep_rounded(ax * cy) - keep_rounded(ay * cx);
  vfloat4 w = keep_rounded(bx * ay) - keep_rounded(by * ax);
  vfloat4 zero(0.0f);
  if (uint32_t on_edge = movemask((u == zero) | (v == zero) | (w == zero))) {
    alignas(16) float fax[4], fay[4], fbx[4], fby[4], fcx[4], fcy[4];
    ax.store_aligned(fax);
    ay.store_aligned(fay);
    bx.store_aligned(fbx);
    by.store_aligned(fby);
    cx.store_aligned(fcx);
    cy.store_aligned(fcy);
    watertight_edges_in_double(fax, fay, fbx, fby, fcx, fcy, on_edge, u, v, w);
  }
  vbool4 negative = (u < zero) | (v < zero) | (w < zero);
  vbool4 positive = (u > zero) | (v > zero) | (w > zero);
  vfloat4 det = u + v + w;
  vfloat4 t_num = u * (r.sz * az) + v * (r.sz * bz) + w * (r.sz * cz);
  return finish_block_hits(det, t_num, v, w, !(negative & positive), r.tmin, tmax, h);
}

/// The watertight block test as a walk's leaf test (bvh/bvh4_leaf_test.h).
struct WatertightBlocks {
  using RayConstants = WatertightBlockRay;
  static constexpr bool kPairs = false;
  PT_ALWAYS_INLINE static uint32_t test(const TriangleBlock4& b, const RayConstants& r, const vfloat4& tmax,
                                        BlockHits& h) {
    return intersect_block_watertight(b, r, tmax, h);
  }
};

}  // namespace PT_ISA_NS
}  // namespace pt::bench
