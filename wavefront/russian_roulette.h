// Stage 5: Russian roulette and compaction. From the second bounce on, each
// continuation survives with probability rr_continue (the throughput its ray
// carries divided by it); survivors are written, in order, to the next
// depth's ray queue.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "streams.h"
#include "wave_context.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// `vertex` = the path vertex the candidates leave from, one where roulette
/// applies (PathRules::roulette_applies; before it, shading writes the next
/// depth's rays itself).
void russian_roulette(const WaveContext& ctx, uint32_t vertex, const RayQueue& candidates, const PathState& paths,
                      RayQueue& next);

}  // namespace PT_ISA_NS
}  // namespace pt::wf
