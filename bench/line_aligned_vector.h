// LineAlignedVector: the benchmarks' ray and hit arrays on 64-byte lines, as
// the wavefront's queues are, so that every tracer reads rays laid out as a
// render hands them over.
#pragma once

#include <vector>

#include <xsimd/memory/xsimd_aligned_allocator.hpp>

namespace pt::bench {

template <class T>
using LineAlignedVector = std::vector<T, xsimd::aligned_allocator<T, 64>>;

}  // namespace pt::bench
