// EngineRunner: builds the acceleration structure the chosen engine traces
// and renders through it (the engines themselves: wavefront/engines.cpp).
#include "render_engines.h"

#include <chrono>

#include "io/scene_error.h"
#include "stage_report.h"
#include "reference/reference_renderer.h"
#include "wavefront/engines.h"

namespace pt::cli {

EngineRunner::EngineRunner(const Options& o, const Scene& scene, const Camera& camera)
    : options_(o), scene_(scene), camera_(camera) {
  auto start = std::chrono::steady_clock::now();
  if (o.accel == AccelChoice::kBvh4) bvh4_ = std::make_unique<SceneBvh4>(scene);
  else
    bvh2_ = std::make_unique<SceneBvh2>(
        scene, o.accel == AccelChoice::kNone ? Bvh2Mode::kBruteForce : Bvh2Mode::kMidpoint, o.max_leaf_size);
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

namespace {

/// Runs a pass-based engine.
RenderOutput render_pass_based(const Options& o, const Scene& scene, const Camera& camera, const RenderSettings& rs,
                               const RenderControl& control, const wf::Tracing& tracing, size_t* queue_bytes) {
  if (o.engine == Engine::kMegakernel) return wf::render_megakernel(scene, camera, rs, tracing, control);
  wf::StageStats stages;
  wf::WavefrontOptions options;
  options.packets = !o.no_packets;
  RenderOutput out = wf::render_wavefront(scene, camera, rs, tracing, options, control, &stages);
  if (o.stats) print_stage_stats(stages, out.stats, o.isa);
  if (queue_bytes) *queue_bytes = stages.queue_bytes;
  return out;
}

}  // namespace

RenderOutput EngineRunner::render(const RenderSettings& rs, const RenderControl& control, size_t* queue_bytes) const {
  if (queue_bytes) *queue_bytes = 0;
  if (options_.engine == Engine::kReference) return reference::render_reference(scene_, *bvh2_, camera_, rs, control);
  wf::Tracing tracing{.bvh4 = bvh4_.get(), .bvh2 = bvh2_.get(), .count_tests = options_.count_tests};
  return render_pass_based(options_, scene_, camera_, rs, control, tracing, queue_bytes);
}

}  // namespace pt::cli
