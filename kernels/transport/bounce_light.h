// The light a BSDF-sampled ray finds where it lands, by the path rules,
// written once for every engine (the wavefront calls it lane by lane): after
// a delta lobe everything it reaches at full weight; otherwise, under MIS,
// the weighted light of the lights it hits (or the sky), plus at full weight
// the emitters that no light sampler knows.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/transport/path_rules.h"
#include "kernels/transport/shading.h"
#include "kernels/transport/surface.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Radiance (before the path's throughput) that bounce ray `vertex`, sampled
/// with solid-angle pdf `bsdf_pdf` or from a delta lobe, brings from its
/// closest hit `hit` with surface `sp` (both null: the ray escaped).
inline float3 light_found_by_bounce(const Scene& s, const RenderSettings& rs, const PathRules& rules, uint32_t vertex,
                                    const Ray& ray, const Hit* hit, const SurfacePoint* sp, float bsdf_pdf,
                                    bool delta) {
  if (delta) return rules.counts(vertex) ? light_found_after_delta(s, rs, ray, sp) : float3{};
  float3 L;
  if (rules.bsdf_competes(vertex)) L = mis_light_found_by_bsdf(s, rs, ray, hit, bsdf_pdf);
  if (sp && emission_found_by_bounce(s, *sp, rs) && rules.counts_emission_found(vertex))
    L += emitted_radiance(s, *sp, ray, rs);
  return L;
}

}  // namespace PT_ISA_NS
}  // namespace pt
