// The queues one worker thread reuses from wave to wave: path state, the
// ray queues of the current and next depth (double-buffered by parity),
// hits, shadow rays, hemisphere rays, continuation candidates, the queues
// by material kind and the order by hit point. Listed once
// (PT_WAVE_BUFFERS) for the members and for their bytes.
#pragma once

#include <cstddef>

#include "kernels/simd/isa_namespace.h"
#include "bvh/queue_scratch.h"
#include "hit_point_order.h"
#include "material_queues.h"
#include "streams.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// What tracing a queue needs besides the queue: the queue tracer's scratch
/// and the occlusion answers of a shadow queue.
struct TracingBuffers {
  QueueScratch scratch;
  std::vector<uint8_t> blocked;
  size_t bytes() const { return scratch.bytes() + blocked.capacity(); }
};

/// X(type, name, extent): a member `type name extent`.
// clang-format off
#define PT_WAVE_BUFFERS(X)                                                              \
  X(PathState, paths, ) X(RayQueue, rays, [2]) X(HitQueue, hits, ) X(ShadowQueue, shadows, ) \
  X(ShadowQueue, hemisphere, ) X(RayQueue, continuations, ) X(MaterialQueues, by_material, ) \
  X(HitPointOrder, hit_order, )
// clang-format on

template <class Stream>
inline size_t stream_bytes(const Stream& s) {
  return s.bytes();
}
template <class Stream, size_t N>
inline size_t stream_bytes(const Stream (&s)[N]) {
  size_t b = 0;
  for (const Stream& x : s) b += x.bytes();
  return b;
}

struct WaveBuffers {
#define PT_WAVE_MEMBER(type, name, extent) type name extent;
  PT_WAVE_BUFFERS(PT_WAVE_MEMBER)
#undef PT_WAVE_MEMBER
  TracingBuffers tracing;  ///< not a queue: its bytes are counted apart

  size_t bytes() const {
#define PT_WAVE_BYTES(type, name, extent) +stream_bytes(name)
    return 0 PT_WAVE_BUFFERS(PT_WAVE_BYTES);
#undef PT_WAVE_BYTES
  }
};

}  // namespace PT_ISA_NS
}  // namespace pt::wf
