// The samplers of K paths, built from the keys their PathState keeps (the
// camera stage computes them once per path).
#pragma once

#include "kernels/path_sampler.h"
#include "kernels/simd.h"
#include "streams.h"

namespace pt::wf {

using SamplerK = PathSamplerT<vuintK, vfloatK>;

/// The sampler of the paths in `path` (indices into `paths`).
inline SamplerK sampler_of_paths(const RenderSettings& rs, const PathState& paths, vintK path) {
  return SamplerK(gather(paths.pixel_key.data(), path), gather(paths.sample_word.data(), path), rs.sampler);
}

}  // namespace pt::wf
