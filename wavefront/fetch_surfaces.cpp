// fetch_surfaces: gathers and the sphere patch; SurfaceLanes.
#include "kernels/simd/isa_namespace.h"
#include "fetch_surfaces.h"

#include <algorithm>

#include "kernels/transport/surface.h"

namespace pt::wf {
inline namespace PT_ISA_NS {
namespace {

/// Forced inline: called out of line at AVX2, each of its six calls spilled
/// the caller's live vector registers.
PT_ALWAYS_INLINE Vec3T<vfloatK> vertex_field(const float* f, vintK vertex, const TriangleArrays& tris) {
  vfloatK c[3];
  gather_records3(f, vertex, tris.vertex_count, c);
  return {c[0], c[1], c[2]};
}

/// Overwrites the sphere lanes with the scalar reconstruction.
void patch_spheres(const WaveContext& ctx, const RayQueue& rays, const HitQueue& hits, size_t i0, uint32_t lanes,
                   SurfaceBatch& s) {
  SurfaceLanes by_lane(s);
  for (; lanes; lanes &= lanes - 1) {
    size_t lane = static_cast<size_t>(__builtin_ctz(lanes)), i = i0 + lane;
    by_lane.set(lane, surface_at(ctx.scene, rays.ray(i), Hit{hits.t[i], hits.u[i], hits.v[i], hits.prim[i]}));
  }
  by_lane.load_into(s);
}

}  // namespace

SurfaceBatch fetch_surfaces(const WaveContext& ctx, const RayQueue& rays, const HitQueue& hits, size_t i0) {
  const TriangleArrays& tris = ctx.triangles;
  SurfaceBatch s;
  vuintK prim = vuintK::load_aligned(&hits.prim[i0]);
  s.valid = xsimd::batch_cast<float>(lane_index()) < vfloatK(static_cast<float>(rays.size - i0));
  vboolK hit = s.valid && as_float_mask(prim != vuintK(kInvalidId));
  vboolK sphere = hit && as_float_mask((prim & vuintK(Hit::kSphereBit)) != vuintK(0u));
  vboolK triangle = hit && !sphere;
  s.hit = hit;

  vintK tri = xsimd::select(as_int_mask(triangle), xsimd::bitwise_cast<vintK>(prim), vintK(0));
  vintK v[3];
  gather_records3(tris.indices, tri, tris.triangle_count, v);
  Vec3T<vfloatK> dir{vfloatK::load_aligned(&rays.dir_x[i0]), vfloatK::load_aligned(&rays.dir_y[i0]),
                     vfloatK::load_aligned(&rays.dir_z[i0])};
  TriangleSurfaceT<vfloatK> ts =
      triangle_surface<vfloatK>(vertex_field(tris.positions, v[0], tris), vertex_field(tris.positions, v[1], tris),
                                vertex_field(tris.positions, v[2], tris), vertex_field(tris.normals, v[0], tris),
                                vertex_field(tris.normals, v[1], tris), vertex_field(tris.normals, v[2], tris),
                                vfloatK::load_aligned(&hits.u[i0]), vfloatK::load_aligned(&hits.v[i0]), dir);
  s.p = ts.p;
  s.ng = ts.ng;
  s.ns = ts.ns;
  s.offset = ts.offset;
  s.front = ts.front;
  s.material = gather(tris.material, tri);
  if (uint32_t sphere_lanes = lane_mask(sphere)) patch_spheres(ctx, rays, hits, i0, sphere_lanes, s);
  return s;
}

SurfaceLanes::SurfaceLanes(const SurfaceBatch& s) {
  const Vec3T<vfloatK>* vecs[3] = {&s.p, &s.ng, &s.ns};
  for (int v = 0; v < 3; ++v) {
    vecs[v]->x.store_aligned(f_[3 * v]);
    vecs[v]->y.store_aligned(f_[3 * v + 1]);
    vecs[v]->z.store_aligned(f_[3 * v + 2]);
  }
  s.offset.store_aligned(f_[9]);
  s.material.store_aligned(material_);
  xsimd::select(as_int_mask(s.front), vintK(1), vintK(0)).store_aligned(front_);
}

void SurfaceLanes::set(size_t lane, const SurfacePoint& sp) {
  const float3* src[3] = {&sp.p, &sp.ng, &sp.ns};
  for (int v = 0; v < 3; ++v)
    for (int c = 0; c < 3; ++c) f_[3 * v + c][lane] = (*src[v])[c];
  f_[9][lane] = sp.offset;
  material_[lane] = static_cast<int32_t>(sp.material);
  front_[lane] = sp.front ? 1 : 0;
}

void SurfaceLanes::load_into(SurfaceBatch& s) const {
  Vec3T<vfloatK>* vecs[3] = {&s.p, &s.ng, &s.ns};
  for (int v = 0; v < 3; ++v)
    *vecs[v] = {vfloatK::load_aligned(f_[3 * v]), vfloatK::load_aligned(f_[3 * v + 1]),
                vfloatK::load_aligned(f_[3 * v + 2])};
  s.offset = vfloatK::load_aligned(f_[9]);
  s.material = vintK::load_aligned(material_);
  s.front = as_float_mask(vintK::load_aligned(front_) != vintK(0));
}

SurfacePoint SurfaceLanes::point(size_t lane) const {
  SurfacePoint sp;
  float3* dst[3] = {&sp.p, &sp.ng, &sp.ns};
  for (int v = 0; v < 3; ++v) *dst[v] = {f_[3 * v][lane], f_[3 * v + 1][lane], f_[3 * v + 2][lane]};
  sp.offset = f_[9][lane];
  sp.material = static_cast<uint32_t>(material_[lane]);
  sp.front = front_[lane] != 0;
  return sp;
}

void prefetch_surfaces(const WaveContext& ctx, const HitQueue& hits, size_t i0, bool vertices) {
  const TriangleArrays& tris = ctx.triangles;
  const size_t end = std::min(hits.size, i0 + kLanes);
  for (size_t i = i0; i < end; ++i) {
    uint32_t prim = hits.prim[i];
    if (prim == kInvalidId || (prim & Hit::kSphereBit)) continue;
    const int32_t* t = tris.indices + 3 * size_t(prim);
    if (!vertices) {
      __builtin_prefetch(t);
      __builtin_prefetch(tris.material + prim);
      continue;
    }
    for (int k = 0; k < 3; ++k) {
      __builtin_prefetch(tris.positions + 3 * size_t(t[k]));
      __builtin_prefetch(tris.normals + 3 * size_t(t[k]));
    }
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
