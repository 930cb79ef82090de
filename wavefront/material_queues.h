// Rays sorted by the kind of material they hit, so that each shading kernel
// runs on lanes that all take the same code (pbrt-v4's per-material queues;
// Laine, Karras and Aila 2013). Rays that escaped go with the diffuse kind,
// whose kernel also adds emission. Allocated only when a scene has more than
// one kind of material: a queue grows when its first ray arrives.
#pragma once

#include <cstddef>

#include "kernels/simd/isa_namespace.h"
#include "kernels/scene/scene.h"
#include "streams.h"
#include "wave_context.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// 68 bytes per ray (a RayQueue item and a HitQueue item), per kind present.
struct MaterialQueues {
  RayQueue rays[kMaterialKindCount];
  HitQueue hits[kMaterialKindCount];

  size_t bytes() const {
    size_t b = 0;
    for (size_t k = 0; k < kMaterialKindCount; ++k) b += rays[k].bytes() + hits[k].bytes();
    return b;
  }
};

/// Splits `rays` and their `hits` into q by material kind, keeping queue
/// order within each kind (SIMD compaction, K lanes at a time).
void bin_by_material(const WaveContext& ctx, const RayQueue& rays, const HitQueue& hits, MaterialQueues& q);

}  // namespace PT_ISA_NS
}  // namespace pt::wf
