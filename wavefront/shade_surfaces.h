// Stage 3: shade the surfaces a ray queue reached, SIMD across rays, one
// kernel per material kind over queues binned by kind (only when the scene
// has more than one). Adds emission where it counts, samples direct light
// (pushing shadow rays, or hemisphere rays with -H), and samples the BSDF for
// the next bounce (pushing continuation candidates that Russian roulette
// then filters, or, before the first vertex where it applies, the next
// depth's rays themselves).
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "material_queues.h"
#include "streams.h"
#include "wave_context.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

struct ShadeOutputs {
  ShadowQueue& shadows;     ///< occlusion rays of light sampling
  ShadowQueue& hemisphere;  ///< closest-hit rays of hemisphere sampling (-H)
  RayQueue& continuations;  ///< next-bounce candidates, before roulette (where it applies)
};

/// `depth` = bounces the rays of `rays` have made (0: camera rays); the
/// surfaces they hit are path vertex depth + 1. `by_material`: the queues
/// by material kind (left empty for diffuse-only scenes).
void shade_surfaces(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits,
                    PathState& paths, ShadeOutputs out, MaterialQueues& by_material);

/// Normal shading: radiance = shading normal * 0.5 + 0.5 at the hit.
void shade_normals(const WaveContext& ctx, const RayQueue& rays, const HitQueue& hits, PathState& paths);

}  // namespace PT_ISA_NS
}  // namespace pt::wf
