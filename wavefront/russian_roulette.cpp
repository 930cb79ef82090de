// russian_roulette: SIMD decisions, scalar compaction.
#include "russian_roulette.h"

#include "kernels/random.h"
#include "kernels/sample_dimensions.h"
#include "lane_output.h"

namespace pt::wf {

void russian_roulette(const WaveContext& ctx, uint32_t vertex, const RayQueue& candidates, PathState& paths,
                      RayQueue& next) {
  const size_t n = candidates.size;
  next.reserve(n);
  next.clear();
  auto keep = [&](size_t i) {
    next.push(candidates.get(i));
  };
  if (vertex < 2) {  // the first indirect bounce is always traced
    for (size_t i = 0; i < n; ++i) keep(i);
    return;
  }
  const float p = ctx.settings.rr_continue;
  const float inv_p = 1.0f / p;
  const uint32_t dim_key = dimension_key(vertex, dims::kRoulette);
  for (size_t i0 = 0; i0 < n; i0 += kLanes) {
    vuintK path = vuintK::load_aligned(&candidates.path[i0]);
    vboolK valid = xsimd::batch_cast<float>(lane_index()) < vfloatK(static_cast<float>(n - i0));
    vintK safe_path = xsimd::select(as_int_mask(valid), xsimd::bitwise_cast<vintK>(path), vintK(0));
    vuintK key = vuintK::gather(paths.key.data(), safe_path);
    vboolK survive = valid && random_float<vuintK, vfloatK>(key, dim_key) < vfloatK(p);
    LaneUints paths_of(path);
    for_each_lane(bitmask(survive), [&](size_t l) {
      uint32_t path_id = paths_of[l];
      paths.beta_r[path_id] *= inv_p;
      paths.beta_g[path_id] *= inv_p;
      paths.beta_b[path_id] *= inv_p;
      keep(i0 + l);
    });
  }
}

}  // namespace pt::wf
