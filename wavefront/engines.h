// The SIMD engines: the wavefront (paths in waves of SoA queues through
// separate stages) and the megakernel it is measured against (each path traced
// start to finish). Both are compiled once per instruction-set level
// (engines_isa.cpp); these entry points run the level active_isa() names.
#pragma once

#include <cstddef>

#include "kernels/simd/isa.h"
#include "kernels/render/render_job.h"
#include "stage_stats.h"
#include "trace_mode.h"

namespace pt {
class SceneBvh2;
class SceneBvh4;
}  // namespace pt

namespace pt::wf {

/// What the engines trace rays with: the 4-wide BVH, or else the midpoint
/// BVH2 or brute force (bvh/scene_bvh2.h).
struct Tracing {
  const SceneBvh4* bvh4 = nullptr;
  const SceneBvh2* bvh2 = nullptr;
  bool count_tests = false;  ///< count primitive tests (BVH4: packets then trace ray by ray)
};

struct WavefrontOptions {
  size_t wave_paths = 8192;  ///< paths per wave (camera samples traced together)
  TraceMode trace = TraceMode::kQueue;
  QueueCapture capture{};         ///< when set, receives every queue traced (trace_mode.h)
  bool sort_by_material = true;   ///< shade from queues binned by material kind (false: every kernel over every ray)
  bool sort_by_hit_point = true;  ///< shade bounce hits in the order of their hit points' cells (hit_point_order.h)
};

/// Renders with the wavefront. If `stage_stats` is given, it receives the
/// per-stage statistics.
RenderOutput render_wavefront(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                              const Tracing& tracing, const WavefrontOptions& options = {},
                              const RenderControl& control = {}, StageStats* stage_stats = nullptr);

/// Renders with the megakernel.
RenderOutput render_megakernel(const Scene& scene, const Camera& camera, const RenderSettings& rs,
                               const Tracing& tracing, const RenderControl& control = {});

/// The engines of one compiled level.
struct EngineTable {
  Isa isa;
  RenderOutput (*wavefront)(const Scene&, const Camera&, const RenderSettings&, const Tracing&, const WavefrontOptions&,
                            const RenderControl&, StageStats*);
  RenderOutput (*megakernel)(const Scene&, const Camera&, const RenderSettings&, const Tracing&, const RenderControl&);
};

/// The table of a level compiled into this binary (IsaError otherwise).
const EngineTable& engine_table(Isa isa);

}  // namespace pt::wf
