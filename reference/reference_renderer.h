// The reference engine: pixels in 16x16 tiles over oneTBB threads, each pixel
// sampled in order (with the assignment's adaptive stopping rule), one path at
// a time through the one-path loop (kernels/transport/path_integrator.h),
// tracing with the midpoint BVH2 or brute force. Compiled once (scalar code):
// it is the arbiter of the SIMD engines at every instruction-set level.
#pragma once

#include "kernels/render/render_job.h"
#include "bvh/scene_bvh2.h"

namespace pt::reference {

struct ReferenceOptions {
  Bvh2Mode accel = Bvh2Mode::kMidpoint;
  uint32_t max_leaf_size = 4;
};

RenderOutput render_reference(const Scene& scene, const Camera& camera, const RenderSettings& settings,
                              const ReferenceOptions& options = {}, const RenderControl& control = {});

/// Same, tracing through an existing accelerator of `scene`.
RenderOutput render_reference(const Scene& scene, const SceneBvh2& accel, const Camera& camera,
                              const RenderSettings& settings, const RenderControl& control = {});

}  // namespace pt::reference
