// The engine the options name, with its acceleration structure built once, so
// that it can render several times (progressive convergence runs).
#pragma once

#include <memory>

#include "bvh/scene_bvh4.h"
#include "cli_options.h"
#include "kernels/render_job.h"
#include "tests/reference/reference_accel.h"

namespace pt::cli {

class EngineRunner {
 public:
  /// Builds the acceleration structure. Throws InputError for combinations that do not exist.
  EngineRunner(const Options& options, const Scene& scene, const Camera& camera);

  RenderOutput render(const RenderSettings& settings, const RenderControl& control) const;
  /// Whether the engine renders in passes (can checkpoint and resume).
  bool pass_based() const { return options_.engine != Engine::kReference; }
  double build_seconds() const { return build_seconds_; }

 private:
  const Options& options_;
  const Scene& scene_;
  const Camera& camera_;
  std::unique_ptr<reference::ReferenceAccel> reference_accel_;  ///< reference engine, or --bvh bvh2 / none
  std::unique_ptr<SceneBvh4> bvh4_;                             ///< wavefront / megakernel with --bvh bvh4
  double build_seconds_ = 0.0;
};

}  // namespace pt::cli
