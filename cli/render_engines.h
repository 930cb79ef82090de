// The engine the options name, with its acceleration structure built once, so
// that it can render several times (progressive convergence runs).
#pragma once

#include <memory>

#include "bvh/scene_bvh4.h"
#include "cli_options.h"
#include "kernels/render/render_job.h"
#include "bvh/scene_bvh2.h"

namespace pt::cli {

class EngineRunner {
 public:
  /// Builds the acceleration structure. Throws InputError for combinations that do not exist.
  EngineRunner(const Options& options, const Scene& scene, const Camera& camera);

  /// `queues`, if given, receives the bytes of the engine's per-thread queues
  /// and of the queue tracer's lists (0 for engines without queues).
  struct QueueBytes {
    size_t queues = 0, tracer = 0;
  };
  RenderOutput render(const RenderSettings& settings, const RenderControl& control, QueueBytes* queues = nullptr) const;
  /// Whether the engine renders in passes (can checkpoint and resume).
  bool pass_based() const { return options_.engine != Engine::kReference; }
  double build_seconds() const { return build_seconds_; }
  /// Bytes of the acceleration structure the engine traces: allocated, and in use.
  size_t accel_bytes() const { return bvh4_ ? bvh4_->bytes() : bvh2_->bytes(); }
  size_t accel_used_bytes() const { return bvh4_ ? bvh4_->used_bytes() : bvh2_->used_bytes(); }

 private:
  const Options& options_;
  const Scene& scene_;
  const Camera& camera_;
  std::unique_ptr<SceneBvh2> bvh2_;  ///< --bvh bvh2 / none (the reference engine's only kind)
  std::unique_ptr<SceneBvh4> bvh4_;  ///< --bvh bvh4 (wavefront / megakernel)
  double build_seconds_ = 0.0;
};

}  // namespace pt::cli
