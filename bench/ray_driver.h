// Runs a ray range function over a whole ray set on N threads: one call on
// the calling thread for N = 1, else chunks of 4096 rays (a multiple of every
// packet width), or of whole queues (fewer rays per chunk in a small set),
// spread over a persistent oneTBB arena of N workers. Every worker flushes
// denormals to zero, as Embree asks, so all tracers run in the same mode.
#pragma once

#include <algorithm>
#include <cstddef>
#include <memory>
#include <vector>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "kernels/simd/simd.h"

namespace pt::bench {

inline constexpr size_t kRayChunk = 4096;

/// The arena of `threads` workers (1..256), created on first use and kept.
inline tbb::task_arena& arena_of(int threads) {
  static std::unique_ptr<tbb::task_arena> arenas[257];
  threads = std::clamp(threads, 1, 256);
  if (!arenas[threads]) arenas[threads] = std::make_unique<tbb::task_arena>(threads);
  return *arenas[threads];
}

/// Calls f(begin, end) over [0, n) in chunks on `threads` threads.
template <class F>
void run_chunks(size_t n, int threads, F&& f) {
  if (threads <= 1) {
    enable_flush_denormals_to_zero();
    f(size_t{0}, n);
    return;
  }
  size_t chunks = (n + kRayChunk - 1) / kRayChunk;
  arena_of(threads).execute([&] {
    tbb::parallel_for(size_t{0}, chunks, [&](size_t c) {
      enable_flush_denormals_to_zero();
      f(c * kRayChunk, std::min(n, (c + 1) * kRayChunk));
    });
  });
}

/// Rays a chunk of whole queues holds at least (run_queues): kRayChunk, or
/// fewer in a set too small for eight chunks per thread (a small scene's
/// captured queues: bunny's 15,733 shadow rays had been four chunks for two
/// threads, teapot's 1,071 one), down to kMinQueueChunk.
inline constexpr size_t kMinQueueChunk = 256;
inline size_t queue_chunk_rays(size_t n, int threads) {
  return std::clamp<size_t>(n / (8 * size_t(threads)), kMinQueueChunk, kRayChunk);
}

/// Calls f(begin, end) over [0, n) on `threads` threads in chunks of whole
/// queues (queue_ends as RaySet's) of at least queue_chunk_rays rays; the
/// last chunk ends at n.
template <class F>
void run_queues(const std::vector<size_t>& queue_ends, size_t n, int threads, F&& f) {
  if (threads <= 1) {
    enable_flush_denormals_to_zero();
    f(size_t{0}, n);
    return;
  }
  const size_t least = queue_chunk_rays(n, threads);
  std::vector<size_t> cuts = {0};
  for (size_t end : queue_ends) {
    if (end >= n) break;
    if (end - cuts.back() >= least) cuts.push_back(end);
  }
  if (cuts.back() < n) cuts.push_back(n);
  arena_of(threads).execute([&] {
    tbb::parallel_for(size_t{0}, cuts.size() - 1, [&](size_t c) {
      enable_flush_denormals_to_zero();
      f(cuts[c], cuts[c + 1]);
    });
  });
}

}  // namespace pt::bench
