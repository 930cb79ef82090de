// The BSDF at one vertex of one path, for the engines that trace a path at a
// time (reference, megakernel): the material's kind picks the Lambertian
// lobe, a delta lobe (mirror, glass, refraction) or the rough conductor, all
// through the lane-generic math the wavefront's per-material kernels run K
// lanes wide (kernels/transport/bsdf.h, kernels/transport/direct_light.h).
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/transport/bsdf.h"
#include "kernels/transport/direct_light.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/render/render_settings.h"
#include "kernels/transport/sample_dimensions.h"
#include "kernels/scene/scene.h"
#include "kernels/transport/surface.h"

namespace pt {
inline namespace PT_ISA_NS {

/// The next direction of a path and what it does to the throughput.
struct BsdfScatter {
  Vec3T<float> wi;  ///< world space
  float pdf = 0;    ///< solid-angle pdf (0 for delta lobes)
  float3 weight;    ///< f cos / pdf
  bool ok = false;
  bool delta = false;
};

/// Conductor parameters of one material (one lane).
inline ConductorT<float> conductor_of(const Material& m) { return {m.alpha, vec3t(m.eta), vec3t(m.k)}; }

class SurfaceBsdf {
 public:
  SurfaceBsdf(const Material& m, const SurfacePoint& sp, const float3& ray_dir, const RenderSettings& rs)
      : m_(m), sp_(sp), course_(rs.cs184_materials), wo_(local_of(vec3t(-ray_dir), vec3t(sp.ns))) {}

  bool lambertian() const { return m_.kind == MaterialKind::kDiffuse; }
  bool delta() const { return is_delta(m_.kind); }
  /// Whether the vertex estimates direct light: a Lambertian surface with a
  /// non-black albedo, or a rough conductor (delta lobes never can).
  bool samples_lights() const { return lambertian() ? !is_black(m_.albedo) : m_.kind == MaterialKind::kMicrofacet; }

  /// Rough conductor only: f(wo, wi) and the pdf of sampling wi (world).
  MicrofacetEvalT<float> eval(const Vec3T<float>& wi) const {
    return eval_microfacet(conductor_of(m_), wo_, local_of(wi, vec3t(sp_.ns)), course_);
  }

  BsdfScatter sample(const ShadingPointT<float>& point, const PathSampler& ps, uint32_t vertex) const {
    BsdfScatter s;
    if (lambertian()) {
      BsdfSampleT<float> bs = sample_lambertian(point, ps, vertex);
      s.wi = bs.wi;
      s.pdf = bs.pdf;
      s.weight = m_.albedo;
      s.ok = bs.ok;
      return s;
    }
    float u1, u2;
    ps.get2d(vertex, dims::kBsdf, u1, u2);
    Vec3T<float> local;
    if (m_.kind == MaterialKind::kMicrofacet) {
      MicrofacetSampleT<float> ms = sample_microfacet(conductor_of(m_), wo_, u1, u2, course_);
      local = ms.wi;
      s.pdf = ms.pdf;
      s.weight = to_float3(ms.weight);
      s.ok = ms.ok;
    } else {
      DeltaScatterT<float> ds =
          m_.kind == MaterialKind::kMirror
              ? DeltaScatterT<float>{mirror_direction(wo_), vec3t(m_.albedo), wo_.z > 0.0f}
              : scatter_dielectric(wo_, sp_.front, m_.ior, vec3t(m_.albedo), vec3t(m_.transmittance), u1,
                                   m_.kind == MaterialKind::kGlass, course_);
      local = ds.wi;
      s.weight = to_float3(ds.weight);
      s.ok = ds.ok;
      s.delta = true;
    }
    s.wi = to_world(sp_.ns.x, sp_.ns.y, sp_.ns.z, local.x, local.y, local.z);
    // Reflection must leave above, refraction below the geometric surface.
    bool above = dot3(s.wi, vec3t(sp_.ng)) > 0.0f;
    s.ok = s.ok && (above == (local.z > 0.0f));
    return s;
  }

 private:
  const Material& m_;
  const SurfacePoint& sp_;
  bool course_;
  Vec3T<float> wo_;
};

}  // namespace PT_ISA_NS
}  // namespace pt
