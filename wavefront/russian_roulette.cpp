// russian_roulette: SIMD decisions, compressed stores for the compaction.
#include "russian_roulette.h"

#include "kernels/transport/path_rules.h"
#include "kernels/transport/sample_dimensions.h"
#include "kernels/transport/shading.h"
#include "lane_output.h"
#include "sampler_lanes.h"

namespace pt::wf {

void russian_roulette(const WaveContext& ctx, uint32_t vertex, const RayQueue& candidates, PathState& paths,
                      RayQueue& next) {
  const size_t n = candidates.size;
  next.reserve(n);
  next.clear();
  const RenderSettings& rs = ctx.settings;
  for (size_t i0 = 0; i0 < n; i0 += kLanes) {
    vboolK valid = xsimd::batch_cast<float>(lane_index()) < vfloatK(static_cast<float>(n - i0));
    if (!PathRules::roulette_applies(vertex)) {
      append_lanes(next, lane_mask(valid), load_lanes(candidates, i0));
      continue;
    }
    vuintK path = vuintK::load_aligned(&candidates.path[i0]);
    vintK safe_path = xsimd::select(as_int_mask(valid), xsimd::bitwise_cast<vintK>(path), vintK(0));
    const SamplerK ps = sampler_of_paths(rs, paths, safe_path);
    vfloatK beta_max =
        xsimd::max(gather(paths.beta_r.data(), safe_path),
                   xsimd::max(gather(paths.beta_g.data(), safe_path), gather(paths.beta_b.data(), safe_path)));
    vfloatK p = continuation_probability(rs, beta_max);
    uint32_t survive = lane_mask(valid && ps.get1d(vertex, dims::kRoulette) < p);
    LaneFloats inv_p(vfloatK(1.0f) / p);
    LaneUints paths_of(path);
    for_each_lane(survive, [&](size_t l) {
      uint32_t path_id = paths_of[l];
      paths.beta_r[path_id] *= inv_p[l];
      paths.beta_g[path_id] *= inv_p[l];
      paths.beta_b[path_id] *= inv_p[l];
    });
    append_lanes(next, survive, load_lanes(candidates, i0));
  }
}

}  // namespace pt::wf
