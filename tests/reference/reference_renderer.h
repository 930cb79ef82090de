// The reference renderer: pixels in 16x16 tiles over oneTBB threads, each pixel
// sampled in order (with the assignment's adaptive stopping rule), one path at
// a time through ReferenceIntegrator.
#pragma once

#include "kernels/render_job.h"
#include "reference_accel.h"

namespace pt::reference {

struct ReferenceOptions {
  AccelMode accel = AccelMode::kBvh;
  uint32_t max_leaf_size = 4;
};

RenderOutput render_reference(const Scene& scene, const Camera& camera, const RenderSettings& settings,
                              const ReferenceOptions& options = {}, const RenderControl& control = {});

/// Same, tracing through an existing accelerator of `scene`.
RenderOutput render_reference(const Scene& scene, const ReferenceAccel& accel, const Camera& camera,
                              const RenderSettings& settings, const RenderControl& control = {});

/// Radiance of one camera sample (pixel index y * width + x, sample s), the
/// unit that the engines' per-sample agreement tests compare.
float3 reference_sample(const Scene& scene, const ReferenceAccel& accel, const Camera& camera,
                        const RenderSettings& settings, int x, int y, uint32_t sample, RenderStats& stats);

}  // namespace pt::reference
