// The engines' entry points: the active level's table.
#include "engines.h"

#include <string>

#include "kernels/isa_list.h"

namespace pt {
#define PT_DECLARE_TABLE(ns, level) \
  namespace ns {                    \
  extern const wf::EngineTable kEngines; \
  }
PT_FOR_EACH_COMPILED_ISA(PT_DECLARE_TABLE)
#undef PT_DECLARE_TABLE
}  // namespace pt

namespace pt::wf {

const EngineTable& engine_table(Isa isa) {
#define PT_TABLE_OF(ns, level) \
  if (isa == Isa::level) return ns::kEngines;
  PT_FOR_EACH_COMPILED_ISA(PT_TABLE_OF)
#undef PT_TABLE_OF
  throw IsaError("this binary has no engines for " + std::string(isa_name(isa)));
}

RenderOutput render_wavefront(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                              const Tracing& tracing, const WavefrontOptions& options, const RenderControl& control,
                              StageStats* stage_stats) {
  return engine_table(active_isa()).wavefront(scene, camera, rs, tracing, options, control, stage_stats);
}

RenderOutput render_megakernel(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                               const Tracing& tracing, const RenderControl& control) {
  return engine_table(active_isa()).megakernel(scene, camera, rs, tracing, control);
}

}  // namespace pt::wf
