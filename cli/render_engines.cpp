// EngineRunner: builds the acceleration structure the chosen engine traces
// and renders through it (the engines themselves: wavefront/engines.cpp).
#include "render_engines.h"

#include <chrono>
#include <cstdio>

#include "io/scene_error.h"
#include "queue_dump.h"
#include "stage_report.h"
#include "reference/reference_renderer.h"
#include "wavefront/engines.h"

namespace pt::cli {

EngineRunner::EngineRunner(const Options& o, const Scene& scene, const Camera& camera)
    : options_(o), scene_(scene), camera_(camera) {
  auto start = std::chrono::steady_clock::now();
  if (o.accel == AccelChoice::kBvh4) {
    Bvh4Options options;
    options.presplit_budget = o.presplit_budget;
    bvh4_ = std::make_unique<SceneBvh4>(scene, options);
  } else
    bvh2_ = std::make_unique<SceneBvh2>(
        scene, o.accel == AccelChoice::kNone ? Bvh2Mode::kBruteForce : Bvh2Mode::kMidpoint, o.max_leaf_size);
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace {

/// Runs a pass-based engine.
RenderOutput render_pass_based(const Options& o, const Scene& scene, const Camera& camera, const RenderSettings& rs,
                               const RenderControl& control, const wf::Tracing& tracing,
                               EngineRunner::QueueBytes* queues) {
  if (o.engine == Engine::kMegakernel) return wf::render_megakernel(scene, camera, rs, tracing, control);
  wf::StageStats stages;
  wf::WavefrontOptions options;
  options.trace = o.trace;
  options.sort_by_hit_point = !o.queue_order_shading;
  QueueDump dump;
  if (!o.dump_queues.empty()) options.capture = dump.hook();
  RenderOutput out = wf::render_wavefront(scene, camera, rs, tracing, options, control, &stages);
  if (!o.dump_queues.empty()) {
    size_t rays = dump.write(o.dump_queues, scene);
    if (!o.quiet) std::printf("Wrote %zu rays of every queue traced to %s\n", rays, o.dump_queues.c_str());
  }
  if (o.stats) print_stage_stats(stages, out.stats, o.isa);
  if (queues) *queues = {stages.queue_bytes, stages.tracer_bytes};
  return out;
}

}  // namespace

RenderOutput EngineRunner::render(const RenderSettings& rs, const RenderControl& control, QueueBytes* queues) const {
  if (queues) *queues = {};
  if (options_.engine == Engine::kReference) return reference::render_reference(scene_, *bvh2_, camera_, rs, control);
  if (options_.stats && bvh4_) print_bvh4_stats(bvh4_->stats());
  wf::Tracing tracing{.bvh4 = bvh4_.get(), .bvh2 = bvh2_.get(), .count_tests = options_.count_tests};
  return render_pass_based(options_, scene_, camera_, rs, control, tracing, queues);
}

}  // namespace pt::cli
