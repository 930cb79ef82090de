// Ray against a block of four triangles (TriangleBlock4) at once: SIMD
// Moller-Trumbore on (v0, e1, e2) rows (the benchmark's watertight test on
// (v0, v1, v2) rows shares its tail, bench/watertight_blocks.h). It compares
// numerators against the determinant and divides only for blocks that have a
// hit. Results follow the
// scalar tests of kernels/scene/triangle_intersect.h: tmin <= t < tmax, u weights
// v1, v weights v2, degenerate triangles and NaN never hit.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "bvh4.h"
#include "kernels/math/ray.h"
#include "kernels/simd/simd.h"

namespace pt {
inline namespace PT_ISA_NS {

/// t, u, v of the four lanes; meaningful in the lanes of the returned mask,
/// and t = +inf in the other lanes.
struct BlockHits {
  vfloat4 t, u, v;
};

/// Per-ray constants of the Moller-Trumbore block test, in lanes of type V.
template <class V>
struct MtRayLanes {
  V org[3], dir[3], tmin;
  MtRayLanes() = default;
  PT_ALWAYS_INLINE explicit MtRayLanes(const Ray& r) : tmin(r.tmin) {
    for (int a = 0; a < 3; ++a) {
      org[a] = V(r.org[a]);
      dir[a] = V(r.dir[a]);
    }
  }
};
using MtBlockRay = MtRayLanes<vfloat4>;

/// t, u, v of a test in lanes of any width; t = +inf where there is no hit.
template <class V>
struct LaneHits {
  V t, u, v;
  typename V::batch_bool_type hit;
};

/// Shared tail of both triangle tests, in lanes of any width: the lanes whose
/// sign-adjusted numerators put the hit inside the triangle and inside
/// [tmin, tmax); t, u, v are divided out only when `any` says some lane
/// passes. Every operation is the same per lane whatever the width, so all
/// widths give the same bits.
template <class V, class B, class AnyFn>
PT_ALWAYS_INLINE bool finish_lanes(const V& det, const V& t_num, const V& u_num, const V& v_num, const B& inside,
                                   const V& tmin, const V& tmax, LaneHits<V>& out, AnyFn any) {
  V sign = xsimd::bitofsign(det);
  V abs_det = det ^ sign;
  V t_abs = t_num ^ sign;
  B valid = inside & (det != V(0.0f)) & (t_abs >= abs_det * tmin) & (t_abs < abs_det * tmax);
  if (!any(valid)) return false;
  V inv = V(1.0f) / det;
  out.t = t_num * inv;
  out.u = u_num * inv;
  out.v = v_num * inv;
  out.hit = valid & (out.t >= tmin) & (out.t < tmax);  // the division may round onto a bound
  out.t = xsimd::select(out.hit, out.t, V(INFINITY));
  return any(out.hit);
}

/// finish_lanes for one block: the mask of lanes hit, their t, u, v in `h`.
PT_ALWAYS_INLINE uint32_t finish_block_hits(vfloat4 det, vfloat4 t_num, vfloat4 u_num, vfloat4 v_num, vbool4 inside,
                                            const vfloat4& tmin, const vfloat4& tmax, BlockHits& h) {
  LaneHits<vfloat4> lanes;
  if (!finish_lanes(det, t_num, u_num, v_num, inside, tmin, tmax, lanes, [](vbool4 m) { return movemask(m) != 0; }))
    return 0;
  h = {lanes.t, lanes.u, lanes.v};
  return movemask(lanes.hit);
}

/// The Moller-Trumbore numerators of a test in lanes of any width, and the
/// lanes where the hit lies inside the triangle (mt_numerators).
template <class V>
struct MtNumerators {
  V det, t_num, u_num, v_num;
  typename V::batch_bool_type inside;
};
/// The part of a test that depends on the direction alone: P = dir x e2 and
/// det = e1 . P. Rays that share one direction (a directional light's) share
/// it, so it can be computed once for all of them, with the same bits.
template <class V>
struct MtDirectionTerms {
  V px, py, pz, det;
};
template <class V, class D>
PT_ALWAYS_INLINE MtDirectionTerms<V> mt_direction_terms(const D (&dir)[3], const V (&e1)[3], const V (&e2)[3]) {
  MtDirectionTerms<V> d;
  d.px = dir[1] * e2[2] - dir[2] * e2[1];
  d.py = dir[2] * e2[0] - dir[0] * e2[2];
  d.pz = dir[0] * e2[1] - dir[1] * e2[0];
  d.det = e1[0] * d.px + e1[1] * d.py + e1[2] * d.pz;
  return d;
}
/// The numerators of a test given its direction terms. `r` is any ray in
/// lanes V (org[3], dir[3]): a block ray repeated over the triangles, or a
/// packet of rays against one triangle repeated over the rays. The one
/// Moller-Trumbore of the BVH4: blocks, block pairs, packets and streams all
/// call it.
template <class V, class R>
PT_ALWAYS_INLINE MtNumerators<V> mt_numerators(const V (&v0)[3], const V (&e1)[3], const V (&e2)[3],
                                               const MtDirectionTerms<V>& d, const R& r) {
  const V &px = d.px, &py = d.py, &pz = d.pz, &det = d.det;
  V tx = r.org[0] - v0[0];
  V ty = r.org[1] - v0[1];
  V tz = r.org[2] - v0[2];
  V u_num = tx * px + ty * py + tz * pz;
  V qx = ty * e1[2] - tz * e1[1];
  V qy = tz * e1[0] - tx * e1[2];
  V qz = tx * e1[1] - ty * e1[0];
  V v_num = r.dir[0] * qx + r.dir[1] * qy + r.dir[2] * qz;
  V t_num = e2[0] * qx + e2[1] * qy + e2[2] * qz;
  V sign = xsimd::bitofsign(det);
  V u_abs = u_num ^ sign, v_abs = v_num ^ sign;
  return {det, t_num, u_num, v_num, (u_abs >= V(0.0f)) & (v_abs >= V(0.0f)) & (u_abs + v_abs <= (det ^ sign))};
}
/// The numerators of a test, its direction terms computed from r.dir.
template <class V, class R>
PT_ALWAYS_INLINE MtNumerators<V> mt_numerators(const V (&v0)[3], const V (&e1)[3], const V (&e2)[3], const R& r) {
  return mt_numerators(v0, e1, e2, mt_direction_terms(r.dir, e1, e2), r);
}

/// Triangle `lane` of a block's rows, repeated over the lanes of V (a
/// triangle against many rays).
template <class V>
struct TriangleRows {
  V v0[3], e1[3], e2[3];
  PT_ALWAYS_INLINE TriangleRows(const TriangleBlock4& b, int lane) {
    for (int a = 0; a < 3; ++a) {
      v0[a] = V(b.v0[a][lane]);
      e1[a] = V(b.r1[a][lane]);
      e2[a] = V(b.r2[a][lane]);
    }
  }
};

/// The direction terms of a block's four triangles for rays that all have
/// one direction (a directional light's shadow rays), computed once for all
/// of them: the same bits as each ray's own test computes.
struct BlockDirectionTerms {
  alignas(16) float px[4], py[4], pz[4], det[4];

  void compute(const TriangleBlock4& b, const vfloat4 (&dir)[3]) {
    vfloat4 e1[3], e2[3];
    for (int a = 0; a < 3; ++a) {
      e1[a] = vfloat4::load_aligned(b.r1[a]);
      e2[a] = vfloat4::load_aligned(b.r2[a]);
    }
    const MtDirectionTerms<vfloat4> d = mt_direction_terms(dir, e1, e2);
    d.px.store_aligned(px), d.py.store_aligned(py), d.pz.store_aligned(pz), d.det.store_aligned(det);
  }
  /// Triangle `lane`'s terms, repeated over the lanes of V.
  template <class V>
  PT_ALWAYS_INLINE MtDirectionTerms<V> of(int lane) const {
    return {V(px[lane]), V(py[lane]), V(pz[lane]), V(det[lane])};
  }
};
static_assert(sizeof(BlockDirectionTerms) == 64);

/// The direction terms of every block of a leaf, for rays of direction
/// `dir`: computed when first asked for, by the first packet or chunk of
/// rays that tests the leaf, and shared by the others.
class LeafDirectionTerms {
 public:
  PT_ALWAYS_INLINE const BlockDirectionTerms* get(const TriangleBlock4* blocks, uint32_t n_blocks,
                                                  const vfloat4 (&dir)[3]) {
    if (!ready_)
      for (uint32_t b = 0; b < n_blocks; ++b) blocks_[b].compute(blocks[b], dir);
    ready_ = true;
    return blocks_;
  }

 private:
  BlockDirectionTerms blocks_[bvh4_ref::kMaxLeafBlocks];
  bool ready_ = false;
};

/// Moller-Trumbore in lanes of any width (finish_lanes decides the hits).
template <class V, class AnyFn>
PT_ALWAYS_INLINE bool mt_lanes(const V (&v0)[3], const V (&e1)[3], const V (&e2)[3], const MtRayLanes<V>& r,
                               const V& tmax, LaneHits<V>& out, AnyFn any) {
  MtNumerators<V> n = mt_numerators(v0, e1, e2, r);
  return finish_lanes(n.det, n.t_num, n.u_num, n.v_num, n.inside, r.tmin, tmax, out, any);
}

/// Moller-Trumbore on a block in kMollerTrumbore form.
PT_ALWAYS_INLINE uint32_t intersect_block_mt(const TriangleBlock4& b, const MtBlockRay& r, const vfloat4& tmax,
                                             BlockHits& h) {
  vfloat4 v0[3], e1[3], e2[3];
  for (int a = 0; a < 3; ++a) {
    v0[a] = vfloat4::load_aligned(b.v0[a]);
    e1[a] = vfloat4::load_aligned(b.r1[a]);
    e2[a] = vfloat4::load_aligned(b.r2[a]);
  }
  LaneHits<vfloat4> lanes;
  if (!mt_lanes(v0, e1, e2, r, tmax, lanes, [](vbool4 m) { return movemask(m) != 0; })) return 0;
  h = {lanes.t, lanes.u, lanes.v};
  return movemask(lanes.hit);
}

#if XSIMD_WITH_AVX2
/// Two consecutive blocks as eight lanes (AVX2 and up): lanes 0-3 are the
/// first block's, 4-7 the second's. Lane for lane the same bits as two calls
/// of intersect_block_mt with the same tmax.
using MtPairRay = MtRayLanes<vfloat8>;

/// The 4-wide ray constants repeated in both halves.
PT_ALWAYS_INLINE MtPairRay widen(const MtBlockRay& r) {
  MtPairRay w;
  for (int a = 0; a < 3; ++a) {
    w.org[a] = repeat_halves(r.org[a]);
    w.dir[a] = repeat_halves(r.dir[a]);
  }
  w.tmin = repeat_halves(r.tmin);
  return w;
}

/// The lanes of one block of a pair: 0 the first, 1 the second.
PT_ALWAYS_INLINE BlockHits block_of_pair(const LaneHits<vfloat8>& h, int which) {
  return {half_of(h.t, which), half_of(h.u, which), half_of(h.v, which)};
}

/// Row `row` (a pointer into the first block) of both blocks.
PT_ALWAYS_INLINE vfloat8 block_pair_row(const float* row) {
  constexpr size_t kNext = sizeof(TriangleBlock4) / sizeof(float);
  return load_halves(row, row + kNext);
}

/// Moller-Trumbore on blocks b[0] and b[1] at once; the mask of lanes hit.
PT_ALWAYS_INLINE uint32_t intersect_block_pair_mt(const TriangleBlock4* b, const MtPairRay& r, const vfloat8& tmax,
                                                  LaneHits<vfloat8>& h) {
  vfloat8 v0[3], e1[3], e2[3];
  for (int a = 0; a < 3; ++a) {
    v0[a] = block_pair_row(b->v0[a]);
    e1[a] = block_pair_row(b->r1[a]);
    e2[a] = block_pair_row(b->r2[a]);
  }
  if (!mt_lanes(v0, e1, e2, r, tmax, h, [](vbool8 m) { return movemask(m) != 0; })) return 0;
  return movemask(h.hit);
}
#endif

}  // namespace PT_ISA_NS
}  // namespace pt
