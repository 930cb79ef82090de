// Rebuilds the surfaces of K hits at once from the scene arrays (SIMD gathers
// of triangle vertices and normals, then the shared triangle_surface math);
// the rare sphere lanes are patched with the scalar surface_at. SurfaceLanes
// hands the lanes to scalar code (emission) without rebuilding them.
#pragma once

#include <cstddef>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/frame.h"
#include "kernels/transport/surface.h"
#include "kernels/simd/simd.h"
#include "streams.h"
#include "wave_context.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

struct SurfaceBatch {
  Vec3T<vfloatK> p, ng, ns;  ///< ng, ns turned towards the incoming ray
  vfloatK offset;            ///< origin offset along ng
  vintK material;
  vboolK hit;    ///< lane holds a surface (a valid ray that hit)
  vboolK valid;  ///< lane holds a ray of the queue
  vboolK front;  ///< the ray arrived on the side the stored normal faces
};

/// The lanes of a SurfaceBatch one by one, as the SurfacePoint surface_at
/// gives (but for raw_ns, which only normal shading reads: left zero).
class SurfaceLanes {
 public:
  explicit SurfaceLanes(const SurfaceBatch& s);
  SurfacePoint point(size_t lane) const;
  void set(size_t lane, const SurfacePoint& sp);  ///< (raw_ns ignored)
  void load_into(SurfaceBatch& s) const;          ///< every field but hit, valid

 private:
  alignas(64) float f_[10][kLanes];  // p, ng, ns (x, y, z each), offset
  alignas(64) int32_t material_[kLanes], front_[kLanes];
};

/// Surfaces of rays [i0, i0 + K) of `rays` with their `hits`.
SurfaceBatch fetch_surfaces(const WaveContext& ctx, const RayQueue& rays, const HitQueue& hits, size_t i0);

/// Starts loading what fetch_surfaces will read for hits [i0, i0 + K): the
/// triangles' vertex indices and materials if `vertices` is false, else their vertices
/// (whose indices should have been prefetched a chunk earlier).
void prefetch_surfaces(const WaveContext& ctx, const HitQueue& hits, size_t i0, bool vertices);

}  // namespace PT_ISA_NS
}  // namespace pt::wf
