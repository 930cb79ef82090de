// EngineRunner: the engine table.
#include "render_engines.h"

#include <chrono>

#include "io/scene_error.h"
#include "stage_report.h"
#include "tests/reference/reference_renderer.h"
#include "wavefront/megakernel_renderer.h"
#include "wavefront/tracers.h"
#include "wavefront/wavefront_renderer.h"

namespace pt::cli {

EngineRunner::EngineRunner(const Options& o, const Scene& scene, const Camera& camera)
    : options_(o), scene_(scene), camera_(camera) {
  auto start = std::chrono::steady_clock::now();
  if (o.accel == AccelChoice::kBvh4) throw InputError("--bvh bvh4 is not available yet; use bvh2 or none");
  bvh2_ = std::make_unique<reference::ReferenceAccel>(
      scene, o.accel == AccelChoice::kNone ? reference::AccelMode::kBruteForce : reference::AccelMode::kBvh,
      o.max_leaf_size);
  build_seconds_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

RenderOutput EngineRunner::render(const RenderSettings& rs, const RenderControl& control, size_t* queue_bytes) const {
  if (queue_bytes) *queue_bytes = 0;
  switch (options_.engine) {
    case Engine::kReference:
      return reference::render_reference(scene_, *bvh2_, camera_, rs, control);
    case Engine::kWavefront: {
      wf::StageStats stages;
      RenderOutput out = wf::render_wavefront(scene_, camera_, rs, wf::Bvh2Tracer{*bvh2_}, {}, control, &stages);
      if (options_.stats) print_stage_stats(stages, out.stats);
      if (queue_bytes) *queue_bytes = stages.queue_bytes;
      return out;
    }
    case Engine::kMegakernel:
      return wf::render_megakernel(scene_, camera_, rs, wf::Bvh2Tracer{*bvh2_}, control);
  }
  throw InputError("unknown engine");
}

}  // namespace pt::cli
