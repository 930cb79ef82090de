// The shading kernels, one per material kind (shade_diffuse.cpp,
// shade_delta.cpp, shade_microfacet.cpp), and the lane helpers they share.
// Each runs over a queue whose rays all hit its kind (or, for the diffuse
// kernel, also escaped); shade_surfaces.cpp decides which run on what.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "fetch_surfaces.h"
#include "kernels/math/frame.h"
#include "kernels/simd/simd.h"
#include "sampler_lanes.h"
#include "shade_surfaces.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

using V3 = Vec3T<vfloatK>;

inline vintK as_index(vuintK u) { return xsimd::bitwise_cast<vintK>(u); }

inline V3 gather3(const AlignedVector<float>& r, const AlignedVector<float>& g, const AlignedVector<float>& b,
                  vintK i) {
  return {gather(r.data(), i), gather(g.data(), i), gather(b.data(), i)};
}

inline V3 times(const V3& a, const V3& b) { return {a.x * b.x, a.y * b.y, a.z * b.z}; }

/// Lanes of `s` that hit a surface of material kind `kind` (all of them in
/// a queue binned by kind).
inline vboolK hits_of_kind(const WaveContext& ctx, const SurfaceBatch& s, MaterialKind kind) {
  vintK k = gather(ctx.materials.kind.data(), s.material);
  return s.hit && as_float_mask(k == vintK(static_cast<int32_t>(kind)));
}

/// Throughput of the paths of the queue's lanes [i0, i0 + K) (unspecified
/// in lanes past its end).
inline V3 lane_beta(const RayQueue& rays, size_t i0) {
  return {vfloatK::load_aligned(&rays.beta_r[i0]), vfloatK::load_aligned(&rays.beta_g[i0]),
          vfloatK::load_aligned(&rays.beta_b[i0])};
}

/// Paths of the queue's lanes [i0, i0 + K) (0 in lanes past its end).
inline vintK lane_paths(const RayQueue& rays, size_t i0, vboolK valid) {
  return xsimd::select(as_int_mask(valid), as_index(vuintK::load_aligned(&rays.path[i0])), vintK(0));
}

/// Lambertian surfaces; also adds the emission of emitters hit and of the
/// sky where escaped rays count.
void shade_diffuse(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits, PathState& paths,
                   ShadeOutputs out);

/// Mirror, glass or refraction (`kind`): one delta lobe, no light samples.
void shade_delta(const WaveContext& ctx, uint32_t depth, MaterialKind kind, const RayQueue& rays, const HitQueue& hits,
                 PathState& paths, ShadeOutputs out);

/// Rough conductors: light samples weighted by the microfacet BRDF, and a
/// Beckmann-sampled continuation.
void shade_microfacet(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits,
                      PathState& paths, ShadeOutputs out);

}  // namespace PT_ISA_NS
}  // namespace pt::wf
