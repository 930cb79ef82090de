// The rules of a path, each written once as a named function that every
// engine (reference, megakernel, wavefront) calls: which bounces count, when
// a vertex estimates direct light, when a BSDF ray leaves it, when that ray
// competes with the light samples under multiple importance sampling, and
// when Russian roulette decides whether it is traced.
//
// Vertex 0 is the camera; vertex v >= 1 is the v-th surface a path reaches.
// Light reflected at vertex v toward the camera has made v bounces; the ray
// that leaves vertex v ("bounce ray v") reaches vertex v + 1.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/render/render_settings.h"
#include "kernels/scene/scene.h"
#include "kernels/transport/shading.h"

namespace pt {
inline namespace PT_ISA_NS {

class PathRules {
 public:
  PathRules(const Scene& scene, const RenderSettings& rs)
      : rs_(rs), mis_(rs.direct == DirectLighting::kMis), final_bounce_(traces_final_bounce(scene, rs)) {}

  /// Light that reaches the camera after `bounces` reflections enters the image.
  bool counts(uint32_t bounces) const { return rs_.counts_bounce(static_cast<int>(bounces)); }
  /// Vertex v estimates the direct light it reflects (light after v bounces).
  bool estimates_direct_light(uint32_t v) const { return counts(v); }
  /// The path goes on from vertex v: bounce ray v may find more vertices.
  bool continues(uint32_t v) const { return static_cast<int>(v) < rs_.max_depth; }
  /// A BSDF ray leaves vertex v: to continue the path, or, from the last
  /// vertex, only to collect the emission no light sampler covers (emissive
  /// meshes; traces_final_bounce).
  bool traces_bsdf_ray(uint32_t v) const {
    return continues(v) || (static_cast<int>(v) == rs_.max_depth && final_bounce_);
  }
  /// A delta lobe (mirror, glass, refraction) at vertex v sends its ray on
  /// up to the last vertex (v == max depth) too: it takes no light sample,
  /// so the light it reflects after v bounces is found only by that ray.
  bool traces_delta_ray(uint32_t v) const { return static_cast<int>(v) <= rs_.max_depth; }
  /// Under MIS, bounce ray v competes with vertex v's light samples: both are
  /// weighted, and the light that ray finds is added (not for the final,
  /// emission-only bounce, and not where vertex v's light does not count).
  bool bsdf_competes(uint32_t v) const { return mis_ && continues(v) && counts(v); }
  /// Russian roulette decides whether bounce ray v is traced: from the second
  /// bounce ray on (the first indirect bounce is always traced).
  static constexpr bool roulette_applies(uint32_t v) { return v >= 2; }
  /// Whether bounce ray v adds, at full weight, the emission of the surface it
  /// reaches (emitters that no light sampler knows; emission_found_by_bounce).
  bool counts_emission_found(uint32_t v) const { return counts(v); }
  /// Whether a ray that escapes the scene adds the sky's radiance: a camera
  /// ray (d = 0) where zero bounces count, bounce ray d where it competes
  /// under MIS (at its MIS weight).
  bool counts_escape(uint32_t d, bool sky_visible) const {
    return sky_visible && (d == 0 ? counts(0) : bsdf_competes(d));
  }

 private:
  const RenderSettings& rs_;
  bool mis_;
  bool final_bounce_;
};

}  // namespace PT_ISA_NS
}  // namespace pt
