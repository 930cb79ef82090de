// --stats: the instruction set the kernels ran at, the wavefront's time per stage, rays per second by ray type and
// paths alive per bounce.
#pragma once

#include "kernels/simd/isa.h"
#include "kernels/render/render_stats.h"
#include "wavefront/stage_stats.h"

namespace pt::cli {

/// `isa`: the level the engine ran at.
void print_stage_stats(const wf::StageStats& stages, const RenderStats& totals, Isa isa);

}  // namespace pt::cli
