// --stats: the instruction set the kernels ran at, the wavefront's time per stage, rays per second by ray type and
// paths alive per bounce.
#pragma once

#include "kernels/simd/isa.h"
#include "bvh/bvh4_build.h"
#include "kernels/render/render_stats.h"
#include "wavefront/stage_stats.h"

namespace pt::cli {

/// `isa`: the level the engine ran at.
void print_stage_stats(const wf::StageStats& stages, const RenderStats& totals, Isa isa);

/// --stats: the BVH4's build (triangles, build references, nodes, leaves, bytes).
void print_bvh4_stats(const Bvh4BuildStats& build);

}  // namespace pt::cli
