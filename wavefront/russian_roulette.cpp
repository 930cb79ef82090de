// russian_roulette: SIMD decisions, compressed stores for the compaction.
#include "kernels/simd/isa_namespace.h"
#include "russian_roulette.h"

#include <cassert>

#include "kernels/transport/path_rules.h"
#include "kernels/transport/sample_dimensions.h"
#include "kernels/transport/shading.h"
#include "lane_output.h"
#include "sampler_lanes.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

void russian_roulette(const WaveContext& ctx, uint32_t vertex, const RayQueue& candidates, const PathState& paths,
                      RayQueue& next) {
  assert(PathRules::roulette_applies(vertex));  // else shading writes the next rays itself
  const size_t n = candidates.size;
  next.reserve(n);
  next.clear();
  const RenderSettings& rs = ctx.settings;
  for (size_t i0 = 0; i0 < n; i0 += kLanes) {
    vboolK valid = xsimd::batch_cast<float>(lane_index()) < vfloatK(static_cast<float>(n - i0));
    RayLanes ray = load_lanes(candidates, i0);
    vintK safe_path = xsimd::select(as_int_mask(valid), xsimd::bitwise_cast<vintK>(ray.path), vintK(0));
    const SamplerK ps = sampler_of_paths(rs, paths, safe_path);
    vfloatK p = continuation_probability(rs, xsimd::max(ray.beta_r, xsimd::max(ray.beta_g, ray.beta_b)));
    uint32_t survive = lane_mask(valid && ps.get1d(vertex, dims::kRoulette) < p);
    const vfloatK inv_p = vfloatK(1.0f) / p;  // survivors' throughput / p
    ray.beta_r = ray.beta_r * inv_p;
    ray.beta_g = ray.beta_g * inv_p;
    ray.beta_b = ray.beta_b * inv_p;
    append_lanes(next, survive, ray);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
