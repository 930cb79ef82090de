// shade_surfaces: the diffuse kernel over the whole queue when every surface
// is diffuse; otherwise the rays binned by material kind, then one kernel
// per kind present (or, unsorted, every kernel over every ray: what sorting
// buys is measured against that).
#include "kernels/simd/isa_namespace.h"
#include "shade_surfaces.h"

#include "kernels/transport/shading.h"
#include "kernels/transport/surface.h"
#include "shade_kernels.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

void shade_surfaces(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits,
                    PathState& paths, ShadeOutputs out, MaterialQueues& by_material) {
  if (ctx.diffuse_only()) {
    shade_diffuse(ctx, depth, rays, hits, paths, out);
    return;
  }
  if (!ctx.sort_by_material) {  // every kernel over every ray, on the lanes of its kind
    shade_diffuse(ctx, depth, rays, hits, paths, out);
    for (uint32_t k = 1; k < kMaterialKindCount; ++k) {
      const MaterialKind kind = static_cast<MaterialKind>(k);
      if (!(ctx.material_kinds & (1u << k))) continue;
      if (kind == MaterialKind::kMicrofacet) shade_microfacet(ctx, depth, rays, hits, paths, out);
      else shade_delta(ctx, depth, kind, rays, hits, paths, out);
    }
    return;
  }
  bin_by_material(ctx, rays, hits, by_material);
  for (uint32_t k = 0; k < kMaterialKindCount; ++k) {
    const RayQueue& q = by_material.rays[k];
    const HitQueue& h = by_material.hits[k];
    if (q.size == 0) continue;
    const MaterialKind kind = static_cast<MaterialKind>(k);
    if (kind == MaterialKind::kDiffuse) shade_diffuse(ctx, depth, q, h, paths, out);
    else if (kind == MaterialKind::kMicrofacet) shade_microfacet(ctx, depth, q, h, paths, out);
    else shade_delta(ctx, depth, kind, q, h, paths, out);
  }
}

void shade_normals(const WaveContext& ctx, const RayQueue& rays, const HitQueue& hits, PathState& paths) {
  for (size_t i = 0; i < rays.size; ++i) {
    if (hits.prim[i] == kInvalidId) continue;
    SurfacePoint sp = surface_at(ctx.scene, rays.ray(i), Hit{hits.t[i], hits.u[i], hits.v[i], hits.prim[i]});
    float3 c = normal_shading_color(sp);
    paths.add_radiance(rays.path[i], c.x, c.y, c.z);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
