// The samplers of K paths, rebuilt from the pixel and sample their PathState
// keeps: two hashes per K paths, 0.9% of a render's instructions. (Keeping
// the keys in PathState instead gave the same images natively, but different
// ones under qemu 7.2's AVX2 emulation, which the emulated-CPU test runs: its
// gathers went wrong wherever the compiler put the index in ymm4, which
// kernels/simd/simd.h now rules out.)
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/simd/simd.h"
#include "streams.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

using SamplerK = PathSamplerT<vuintK, vfloatK>;

/// The sampler of the paths in `path` (indices into `paths`).
inline SamplerK sampler_of_paths(const RenderSettings& rs, const PathState& paths, vintK path) {
  return SamplerK(rs, gather(paths.pixel.data(), path), gather(paths.sample.data(), path));
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
