// Ray against a block of four triangles (TriangleBlock4) at once: SIMD
// Moller-Trumbore on (v0, e1, e2) rows and the watertight test of Woop, Benthin
// and Wald (2013) on (v0, v1, v2) rows. Both compare numerators against the
// determinant and divide only for blocks that have a hit. Results follow the
// scalar tests of kernels/triangle_intersect.h: tmin <= t < tmax, u weights
// v1, v weights v2, degenerate triangles and NaN never hit.
#pragma once

#include <cstdint>

#include "bvh4.h"
#include "kernels/ray.h"
#include "kernels/simd.h"

namespace pt {

/// t, u, v of the four lanes; meaningful in the lanes of the returned mask,
/// and t = +inf in the other lanes.
struct BlockHits {
  vfloat4 t, u, v;
};

/// Per-ray constants of the Moller-Trumbore block test.
struct MtBlockRay {
  vfloat4 org[3], dir[3], tmin;
  PT_ALWAYS_INLINE explicit MtBlockRay(const Ray& r) : tmin(r.tmin) {
    for (int a = 0; a < 3; ++a) { org[a] = vfloat4(r.org[a]); dir[a] = vfloat4(r.dir[a]); }
  }
};

/// Shared tail: lanes whose sign-adjusted numerators put the hit inside the
/// triangle and inside [tmin, tmax); divides only when some lane passes.
PT_ALWAYS_INLINE uint32_t finish_block_hits(vfloat4 det, vfloat4 t_num, vfloat4 u_num, vfloat4 v_num,
                                            vbool4 inside, const vfloat4& tmin, const vfloat4& tmax, BlockHits& h) {
  vfloat4 sign = xsimd::bitofsign(det);
  vfloat4 abs_det = det ^ sign;
  vfloat4 t_abs = t_num ^ sign;
  vbool4 valid = inside & (det != vfloat4(0.0f)) & (t_abs >= abs_det * tmin) & (t_abs < abs_det * tmax);
  if (movemask(valid) == 0) return 0;
  vfloat4 inv = vfloat4(1.0f) / det;
  h.t = t_num * inv;
  h.u = u_num * inv;
  h.v = v_num * inv;
  vbool4 hit = valid & (h.t >= tmin) & (h.t < tmax);  // the division may round onto a bound
  h.t = xsimd::select(hit, h.t, vfloat4(INFINITY));
  return movemask(hit);
}

/// Moller-Trumbore on a block in kMollerTrumbore form.
PT_ALWAYS_INLINE uint32_t intersect_block_mt(const TriangleBlock4& b, const MtBlockRay& r, const vfloat4& tmax,
                                             BlockHits& h) {
  vfloat4 e1x = vfloat4::load_aligned(b.r1[0]), e1y = vfloat4::load_aligned(b.r1[1]), e1z = vfloat4::load_aligned(b.r1[2]);
  vfloat4 e2x = vfloat4::load_aligned(b.r2[0]), e2y = vfloat4::load_aligned(b.r2[1]), e2z = vfloat4::load_aligned(b.r2[2]);
  vfloat4 px = r.dir[1] * e2z - r.dir[2] * e2y;
  vfloat4 py = r.dir[2] * e2x - r.dir[0] * e2z;
  vfloat4 pz = r.dir[0] * e2y - r.dir[1] * e2x;
  vfloat4 det = e1x * px + e1y * py + e1z * pz;
  vfloat4 tx = r.org[0] - vfloat4::load_aligned(b.v0[0]);
  vfloat4 ty = r.org[1] - vfloat4::load_aligned(b.v0[1]);
  vfloat4 tz = r.org[2] - vfloat4::load_aligned(b.v0[2]);
  vfloat4 u_num = tx * px + ty * py + tz * pz;
  vfloat4 qx = ty * e1z - tz * e1y;
  vfloat4 qy = tz * e1x - tx * e1z;
  vfloat4 qz = tx * e1y - ty * e1x;
  vfloat4 v_num = r.dir[0] * qx + r.dir[1] * qy + r.dir[2] * qz;
  vfloat4 t_num = e2x * qx + e2y * qy + e2z * qz;
  vfloat4 sign = xsimd::bitofsign(det);
  vfloat4 u_abs = u_num ^ sign, v_abs = v_num ^ sign;
  vbool4 inside = (u_abs >= vfloat4(0.0f)) & (v_abs >= vfloat4(0.0f)) & (u_abs + v_abs <= (det ^ sign));
  return finish_block_hits(det, t_num, u_num, v_num, inside, r.tmin, tmax, h);
}

/// Per-ray constants of the watertight test: the dominant direction axis
/// becomes z (kz), the shear maps the direction onto +z.
struct WatertightBlockRay {
  uint32_t kx, ky, kz;
  vfloat4 org[3];  ///< origin in permuted order (x = org[kx], ...)
  vfloat4 sx, sy, sz, tmin;
  explicit WatertightBlockRay(const Ray& r);
};

/// Recomputes the edge functions of the lanes where one is exactly zero in
/// double precision (products of floats are exact there), as Woop et al. do.
void watertight_edges_in_double(const float ax[4], const float ay[4], const float bx[4], const float by[4],
                                const float cx[4], const float cy[4], uint32_t lanes, vfloat4& u, vfloat4& v,
                                vfloat4& w);

/// Watertight test on a block in kWatertight form.
PT_ALWAYS_INLINE uint32_t intersect_block_watertight(const TriangleBlock4& b, const WatertightBlockRay& r,
                                                     const vfloat4& tmax, BlockHits& h) {
  auto row = [](const float (*rows)[4], uint32_t axis) { return vfloat4::load_aligned(rows[axis]); };
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
    ax.store_aligned(fax); ay.store_aligned(fay); bx.store_aligned(fbx);
    by.store_aligned(fby); cx.store_aligned(fcx); cy.store_aligned(fcy);
    watertight_edges_in_double(fax, fay, fbx, fby, fcx, fcy, on_edge, u, v, w);
  }
  vbool4 negative = (u < zero) | (v < zero) | (w < zero);
  vbool4 positive = (u > zero) | (v > zero) | (w > zero);
  vfloat4 det = u + v + w;
  vfloat4 t_num = u * (r.sz * az) + v * (r.sz * bz) + w * (r.sz * cz);
  return finish_block_hits(det, t_num, v, w, !(negative & positive), r.tmin, tmax, h);
}

}  // namespace pt
