// russian_roulette: SIMD decisions, scalar compaction.
#include "russian_roulette.h"

#include "kernels/random.h"
#include "kernels/sample_dimensions.h"
#include "kernels/shading.h"
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
  const RenderSettings& rs = ctx.settings;
  const uint32_t dim_key = dimension_key(vertex, dims::kRoulette);
  for (size_t i0 = 0; i0 < n; i0 += kLanes) {
    vuintK path = vuintK::load_aligned(&candidates.path[i0]);
    vboolK valid = xsimd::batch_cast<float>(lane_index()) < vfloatK(static_cast<float>(n - i0));
    vintK safe_path = xsimd::select(as_int_mask(valid), xsimd::bitwise_cast<vintK>(path), vintK(0));
    vuintK pixel_k = gather(paths.pixel_key.data(), safe_path);
    vuintK sample_k = gather(paths.sample_key.data(), safe_path);
    vfloatK beta_max = xsimd::max(gather(paths.beta_r.data(), safe_path),
                                  xsimd::max(gather(paths.beta_g.data(), safe_path),
                                             gather(paths.beta_b.data(), safe_path)));
    vfloatK p = continuation_probability(rs, beta_max);
    vboolK survive = valid && random_float<vuintK, vfloatK>(pixel_k, sample_k, dim_key) < p;
    LaneFloats inv_p(vfloatK(1.0f) / p);
    LaneUints paths_of(path);
    for_each_lane(lane_mask(survive), [&](size_t l) {
      uint32_t path_id = paths_of[l];
      paths.beta_r[path_id] *= inv_p[l];
      paths.beta_g[path_id] *= inv_p[l];
      paths.beta_b[path_id] *= inv_p[l];
      keep(i0 + l);
    });
  }
}

}  // namespace pt::wf
