// How the wavefront traces its queues (--trace): every queue whole through
// the BVH's queue tracer (the default), or every ray on its own (for
// comparison); and the hook that receives a copy of every queue (ray dumps,
// benchmarks).
#pragma once

#include <cstdint>
#include <functional>
#include <span>

#include "kernels/math/ray.h"

namespace pt::wf {

enum class TraceMode {
  kQueue,   ///< every queue whole through the queue tracer, which picks each queue's method (docs/bvh.md)
  kSingle,  ///< every ray on its own, through the single-ray queries (for comparison)
};

/// The queues a wave traces.
enum class QueueKind {
  kCamera,      ///< closest hit, depth 0
  kBounce,      ///< closest hit, depth >= 1
  kShadow,      ///< occlusion (light samples), from the hits of depth d
  kHemisphere,  ///< closest hit (hemisphere and cosine estimators), from the hits of depth d
};
inline const char* queue_kind_name(QueueKind k) {
  switch (k) {
    case QueueKind::kCamera: return "camera";
    case QueueKind::kBounce: return "bounce";
    case QueueKind::kShadow: return "shadow";
    case QueueKind::kHemisphere: return "hemisphere";
  }
  return "?";
}

/// Receives a copy of every queue a wave traces, just before it is traced;
/// called from the worker threads, one wave at a time per thread.
using QueueCapture = std::function<void(QueueKind kind, uint32_t depth, std::span<const Ray> rays)>;

}  // namespace pt::wf
