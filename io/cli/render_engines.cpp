// render_with_engine: the engine table.
#include "render_engines.h"

#include "io/scene_error.h"
#include "tests/reference/reference_renderer.h"
#include "wavefront/megakernel_renderer.h"
#include "wavefront/tracers.h"
#include "wavefront/wavefront_renderer.h"
#include "stage_report.h"

namespace pt::cli {

RenderOutput render_with_engine(const Options& o, const Scene& scene, const Camera& camera,
                                const RenderControl& control) {
  switch (o.engine) {
    case Engine::kReference: {
      reference::ReferenceOptions ro;
      if (o.accel == AccelChoice::kBvh4) throw InputError("--bvh bvh4 is not available yet; use bvh2 or none");
      ro.accel = o.accel == AccelChoice::kNone ? reference::AccelMode::kBruteForce : reference::AccelMode::kBvh;
      ro.max_leaf_size = o.max_leaf_size;
      return reference::render_reference(scene, camera, o.settings, ro, control);
    }
    case Engine::kWavefront: {
      if (o.accel == AccelChoice::kBvh4) throw InputError("--bvh bvh4 is not available yet; use bvh2");
      reference::ReferenceAccel accel(scene, o.accel == AccelChoice::kNone ? reference::AccelMode::kBruteForce
                                                                            : reference::AccelMode::kBvh,
                                      o.max_leaf_size);
      wf::StageStats stages;
      RenderOutput out = wf::render_wavefront(scene, camera, o.settings, wf::Bvh2Tracer{accel}, {}, control, &stages);
      if (o.stats) print_stage_stats(stages, out.stats);
      return out;
    }
    case Engine::kMegakernel: {
      if (o.accel == AccelChoice::kBvh4) throw InputError("--bvh bvh4 is not available yet; use bvh2");
      reference::ReferenceAccel accel(scene, o.accel == AccelChoice::kNone ? reference::AccelMode::kBruteForce
                                                                            : reference::AccelMode::kBvh,
                                      o.max_leaf_size);
      return wf::render_megakernel(scene, camera, o.settings, wf::Bvh2Tracer{accel}, control);
    }
  }
  throw InputError("unknown engine");
}

}  // namespace pt::cli
