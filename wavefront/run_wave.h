// One wave through the pipeline: generate camera rays, then per depth
// intersect closest -> shade surfaces -> trace shadow rays -> Russian
// roulette, until no path continues. Reads like the pipeline it is.
#pragma once

#include <span>

#include "generate_camera_rays.h"
#include "intersect_closest.h"
#include "russian_roulette.h"
#include "shade_surfaces.h"
#include "stage_stats.h"
#include "trace_shadow_rays.h"
#include "wave_buffers.h"

namespace pt::wf {

/// Renders samples [first_sample, first_sample + samples) of `pixels`; the
/// radiance of path i ends up in b.paths (path i <-> pixel i / samples).
/// `packets`: trace the coherent queues (camera rays, and shadow rays from the
/// camera rays' hits) as SIMD packets.
template <class Tracer>
void run_wave(const WaveContext& ctx, const Tracer& tracer, std::span<const uint32_t> pixels, uint32_t first_sample,
              uint32_t samples, bool packets, WaveBuffers& b, StageStats& stats) {
  {
    StageTimer t(stats, Stage::kGenerate);
    generate_camera_rays(ctx, pixels, first_sample, samples, b.paths, b.rays[0]);
  }
  stats.camera_rays += b.rays[0].size;
  int cur = 0;
  for (uint32_t depth = 0; b.rays[cur].size > 0; ++depth) {
    RayQueue& rays = b.rays[cur];
    stats.count_alive(depth, rays.size);
    {
      StageTimer t(stats, depth == 0 ? Stage::kIntersectCamera : Stage::kIntersectBounce);
      intersect_closest(tracer, rays, b.hits, stats.primitive_tests, packets && depth == 0);
    }
    if (ctx.settings.shading == ShadingMode::kNormals) {
      StageTimer t(stats, Stage::kShade);
      shade_normals(ctx, rays, b.hits, b.paths);
      break;
    }
    b.shadows.clear();
    b.hemisphere.clear();
    b.continuations.clear();
    {
      StageTimer t(stats, Stage::kShade);
      shade_surfaces(ctx, depth, rays, b.hits, b.paths, {b.shadows, b.hemisphere, b.continuations}, b.by_material);
    }
    {
      StageTimer t(stats, depth == 0 ? Stage::kShadowFirstHit : Stage::kShadowLater);
      trace_shadow_rays(tracer, b.shadows, b.paths, stats.primitive_tests, packets && depth == 0);
      trace_hemisphere_rays(tracer, ctx, b.hemisphere, b.paths, stats.primitive_tests);
    }
    stats.shadow_rays += b.shadows.size + b.hemisphere.size;
    if (depth == 0) stats.first_hit_shadow_rays += b.shadows.size + b.hemisphere.size;
    {
      StageTimer t(stats, Stage::kRoulette);
      russian_roulette(ctx, depth + 1, b.continuations, b.paths, b.rays[1 - cur]);
    }
    cur = 1 - cur;
    stats.bounce_rays += b.rays[cur].size;
  }
}

}  // namespace pt::wf
