// The engines' entry points: the active level's table.
#include "engines.h"

#include "kernels/simd/isa_list.h"

namespace pt {
PT_DECLARE_ISA_TABLES(wf::EngineTable, kEngines)
}  // namespace pt

namespace pt::wf {

const EngineTable& engine_table(Isa isa) { return isa_table(isa, {PT_ISA_TABLE_ADDRESSES(kEngines)}, "engines"); }

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
