// One wave through the pipeline: generate camera rays, then per depth
// intersect closest -> (below depth 0) sort by hit point -> shade surfaces ->
// trace shadow rays -> Russian roulette, until no path continues. Reads like
// the pipeline it is.
#pragma once

#include <span>
#include <vector>

#include "kernels/simd/isa_namespace.h"
#include "engines.h"
#include "generate_camera_rays.h"
#include "hit_point_order.h"
#include "intersect_closest.h"
#include "kernels/transport/path_rules.h"
#include "russian_roulette.h"
#include "shade_surfaces.h"
#include "stage_stats.h"
#include "trace_shadow_rays.h"
#include "wave_buffers.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// Hands a copy of `queue` to options.capture, if set.
template <class Queue>
void capture_queue(const WavefrontOptions& options, QueueKind kind, uint32_t depth, const Queue& queue) {
  if (!options.capture || queue.size == 0) return;
  std::vector<Ray> rays(queue.size);
  for (size_t i = 0; i < queue.size; ++i) rays[i] = queue.ray(i);
  options.capture(kind, depth, rays);
}

/// Renders samples [first_sample, first_sample + samples) of `pixels`; the
/// radiance of path i ends up in b.paths (path i <-> pixel i / samples).
/// options.trace: how the queues are traced (trace_mode.h).
template <class Tracer>
void run_wave(const WaveContext& ctx, const Tracer& tracer, std::span<const uint32_t> pixels, uint32_t first_sample,
              uint32_t samples, const WavefrontOptions& options, WaveBuffers& b, StageStats& stats) {
  const TraceMode mode = options.trace;
  {
    StageTimer t(stats, Stage::kGenerate);
    generate_camera_rays(ctx, pixels, first_sample, samples, b.paths, b.rays[0]);
  }
  stats.camera_rays += b.rays[0].size;
  int cur = 0;
  for (uint32_t depth = 0; b.rays[cur].size > 0; ++depth) {
    RayQueue& rays = b.rays[cur];
    stats.count_alive(depth, rays.size);
    capture_queue(options, depth == 0 ? QueueKind::kCamera : QueueKind::kBounce, depth, rays);
    {
      StageTimer t(stats, depth == 0 ? Stage::kIntersectCamera : Stage::kIntersectBounce);
      QueueTimer q(stats, depth == 0 ? TracedQueue::kCamera : TracedQueue::kBounce, rays.size);
      intersect_closest(tracer, rays, b.hits, b.tracing, stats.primitive_tests, mode);
    }
    if (depth > 0 && options.sort_by_hit_point) {  // camera rays' hits come in pixel order already
      StageTimer t(stats, Stage::kSortHits);
      sort_by_hit_point(ctx.scene.bounds, rays, b.hits, b.hit_order);
    }
    if (ctx.settings.shading == ShadingMode::kNormals) {
      StageTimer t(stats, Stage::kShade);
      shade_normals(ctx, rays, b.hits, b.paths);
      break;
    }
    // Without roulette at the next vertex the continuations are the next
    // depth's rays as they are: shading writes them there directly.
    const bool roulette = PathRules::roulette_applies(depth + 1);
    RayQueue& continuations = roulette ? b.continuations : b.rays[1 - cur];
    b.shadows.clear();
    b.hemisphere.clear();
    continuations.clear();
    continuations.reserve(rays.size);  // as the roulette stage reserves its output: every kernel's appends fit
    {
      StageTimer t(stats, Stage::kShade);
      shade_surfaces(ctx, depth, rays, b.hits, b.paths, {b.shadows, b.hemisphere, continuations}, b.by_material);
    }
    capture_queue(options, QueueKind::kShadow, depth, b.shadows);
    capture_queue(options, QueueKind::kHemisphere, depth, b.hemisphere);
    {
      StageTimer t(stats, depth == 0 ? Stage::kShadowFirstHit : Stage::kShadowLater);
      {
        QueueTimer q(stats, depth == 0 ? TracedQueue::kShadowFirstHit : TracedQueue::kShadowLater, b.shadows.size);
        find_blocked(tracer, b.shadows, b.tracing, stats.primitive_tests, mode);
      }
      add_unblocked(b.shadows, b.tracing, b.paths);
      if (b.hemisphere.size > 0) {
        {
          QueueTimer q(stats, TracedQueue::kHemisphere, b.hemisphere.size);
          intersect_closest(tracer, b.hemisphere, b.hits, b.tracing, stats.primitive_tests, mode);
        }
        add_found_emission(ctx, b.hemisphere, b.hits, b.paths);
      }
    }
    stats.shadow_rays += b.shadows.size + b.hemisphere.size;
    if (depth == 0) stats.first_hit_shadow_rays += b.shadows.size + b.hemisphere.size;
    {
      StageTimer t(stats, Stage::kRoulette);
      if (roulette) russian_roulette(ctx, depth + 1, b.continuations, b.paths, b.rays[1 - cur]);
    }
    cur = 1 - cur;
    stats.bounce_rays += b.rays[cur].size;
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
