// render_with_engine: the engine table.
#include "render_engines.h"

#include "io/scene_error.h"
#include "tests/reference/reference_renderer.h"

namespace pt::cli {

RenderOutput render_with_engine(const Options& o, const Scene& scene, const Camera& camera,
                                const RenderControl& control) {
  switch (o.engine) {
    case Engine::kReference: {
      reference::ReferenceOptions ro;
      ro.accel = o.accel == AccelChoice::kNone   ? reference::AccelMode::kBruteForce
                 : o.accel == AccelChoice::kBvh2 ? reference::AccelMode::kBvh
                                                 : reference::AccelMode::kBvh4;
      ro.max_leaf_size = o.max_leaf_size;
      return reference::render_reference(scene, camera, o.settings, ro, control);
    }
    case Engine::kWavefront:
    case Engine::kMegakernel:
      throw InputError(std::string("--engine ") + engine_name(o.engine) + " is not available yet");
  }
  throw InputError("unknown engine");
}

}  // namespace pt::cli
