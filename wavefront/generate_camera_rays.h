// Stage 1: camera rays for a wave of paths, SIMD across paths. Path i of the
// wave is sample first_sample + i % samples of pixel pixels[i / samples].
#pragma once

#include <span>

#include "kernels/simd/isa_namespace.h"
#include "streams.h"
#include "wave_context.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// Initialises paths [0, n) (identity, random key, radiance 0) and writes
/// their camera rays to `rays` (ray i belongs to path i; throughput 1).
void generate_camera_rays(const WaveContext& ctx, std::span<const uint32_t> pixels, uint32_t first_sample,
                          uint32_t samples, PathState& paths, RayQueue& rays);

}  // namespace PT_ISA_NS
}  // namespace pt::wf
