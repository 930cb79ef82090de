// The engine table of one instruction-set level (compiled once per level, see
// kernels/simd/isa.h): the wavefront and the megakernel instantiated over each
// tracer.
#include "bvh/tracers.h"
#include "engines.h"
#include "megakernel_renderer.h"
#include "wavefront_renderer.h"

namespace pt::wf {
inline namespace PT_ISA_NS {
namespace {

/// Calls render(tracer) with the tracer `tracing` names.
template <class Render>
RenderOutput with_tracer(const Tracing& tracing, Render&& render) {
  if (!tracing.bvh4) return render(Bvh2Tracer{*tracing.bvh2});
  if (tracing.count_tests) return render(Bvh4Tracer<true>{*tracing.bvh4});
  return render(Bvh4Tracer<false>{*tracing.bvh4});
}

RenderOutput wavefront(const Scene& scene, const Camera& camera, const RenderSettings& rs, const Tracing& tracing,
                       const WavefrontOptions& options, const RenderControl& control, StageStats* stage_stats) {
  return with_tracer(tracing, [&](const auto& tracer) {
    return render_wavefront_with(scene, camera, rs, tracer, options, control, stage_stats);
  });
}

RenderOutput megakernel(const Scene& scene, const Camera& camera, const RenderSettings& rs, const Tracing& tracing,
                        const RenderControl& control) {
  return with_tracer(tracing,
                     [&](const auto& tracer) { return render_megakernel_with(scene, camera, rs, tracer, control); });
}

}  // namespace
}  // namespace PT_ISA_NS
}  // namespace pt::wf

namespace pt {
inline namespace PT_ISA_NS {
extern const wf::EngineTable kEngines;
const wf::EngineTable kEngines = {.isa = PT_ISA, .wavefront = wf::wavefront, .megakernel = wf::megakernel};
}  // namespace PT_ISA_NS
}  // namespace pt
