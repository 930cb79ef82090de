// Per-thread statistics of the wavefront: time per stage, time in the queue
// tracer per kind of queue, rays by type, primitive tests, and how many paths
// are alive at each depth.
#pragma once

#include <array>
#include <chrono>
#include <cstdint>
#include <vector>

#include "kernels/simd/isa_namespace.h"

namespace pt::wf {

/// Intersection stages are split by ray coherence: camera rays and shadow
/// rays from the camera rays' hits (coherent) apart from bounce rays and later
/// shadow rays (incoherent).
enum class Stage : int {
  kGenerate,
  kIntersectCamera,
  kIntersectBounce,
  kSortHits,
  kShade,
  kShadowFirstHit,
  kShadowLater,
  kRoulette,
  kAccumulate,
  kCount
};
inline constexpr const char* kStageNames[] = {"generate_camera_rays",
                                              "intersect_closest (camera)",
                                              "intersect_closest (bounce)",
                                              "sort_by_hit_point",
                                              "shade_surfaces",
                                              "trace_shadow_rays (1st hit)",
                                              "trace_shadow_rays (later)",
                                              "russian_roulette",
                                              "accumulate"};

/// The queues the tracer is handed, by kind (the tracer's time is part of the
/// intersection and shadow stages' time): the queue tracer's time, or with
/// --trace single that of single rays.
enum class TracedQueue : int { kCamera, kBounce, kShadowFirstHit, kShadowLater, kHemisphere, kCount };
inline constexpr const char* kTracedQueueNames[] = {"camera rays", "bounce rays", "shadow rays from first hits",
                                                    "later shadow rays", "hemisphere rays"};

/// Queues of one kind: how many, their rays, and the time the tracer took.
struct QueueTiming {
  uint64_t queues = 0, rays = 0;
  double seconds = 0.0;
};

struct StageStats {
  std::array<double, static_cast<int>(Stage::kCount)> seconds{};
  std::array<QueueTiming, static_cast<int>(TracedQueue::kCount)> traced{};
  uint64_t camera_rays = 0, bounce_rays = 0, shadow_rays = 0;
  uint64_t first_hit_shadow_rays = 0;  ///< shadow rays from the camera rays' hits
  uint64_t primitive_tests = 0;
  std::vector<uint64_t> paths_alive;  ///< index = depth (0 = camera rays)
  size_t queue_bytes = 0;             ///< bytes the wave buffers held at the end (all threads)
  size_t tracer_bytes = 0;            ///< bytes of the queue tracer's lists and answers at the end (all threads)

  void count_alive(uint32_t depth, uint64_t n) {
    if (paths_alive.size() <= depth) paths_alive.resize(depth + 1, 0);
    paths_alive[depth] += n;
  }
  StageStats& operator+=(const StageStats& o) {
    for (size_t i = 0; i < seconds.size(); ++i) seconds[i] += o.seconds[i];
    for (size_t i = 0; i < traced.size(); ++i) {
      traced[i].queues += o.traced[i].queues;
      traced[i].rays += o.traced[i].rays;
      traced[i].seconds += o.traced[i].seconds;
    }
    camera_rays += o.camera_rays;
    bounce_rays += o.bounce_rays;
    shadow_rays += o.shadow_rays;
    first_hit_shadow_rays += o.first_hit_shadow_rays;
    primitive_tests += o.primitive_tests;
    queue_bytes += o.queue_bytes;
    tracer_bytes += o.tracer_bytes;
    for (size_t d = 0; d < o.paths_alive.size(); ++d) count_alive(static_cast<uint32_t>(d), o.paths_alive[d]);
    return *this;
  }
};

inline namespace PT_ISA_NS {
/// Adds the scope's wall time to one stage.
class StageTimer {
 public:
  StageTimer(StageStats& s, Stage stage) : stats_(s), stage_(stage), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    stats_.seconds[static_cast<int>(stage_)] +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  StageStats& stats_;
  Stage stage_;
  std::chrono::steady_clock::time_point start_;
};

/// Adds the scope's wall time to one kind of queue, for a non-empty queue.
class QueueTimer {
 public:
  QueueTimer(StageStats& s, TracedQueue kind, size_t rays)
      : timing_(rays ? &s.traced[static_cast<int>(kind)] : nullptr), start_(std::chrono::steady_clock::now()) {
    if (timing_) {
      ++timing_->queues;
      timing_->rays += rays;
    }
  }
  ~QueueTimer() {
    if (timing_) timing_->seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }

 private:
  QueueTiming* timing_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace PT_ISA_NS
}  // namespace pt::wf
