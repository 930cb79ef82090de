// One benchmark scene with everything its timings need: the triangles, the
// ray sets (camera rays; diffuse and shadow rays from their hits, shuffled
// and in the camera rays' order; the bounce and shadow queues of a real
// render), the oracle's answers (the reference binary BVH, whose triangle
// test is the brute-force one), and every tracer under test behind one
// interface, each validated ray by ray before it is timed.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bench_queries.h"
#include "bvh/scene_bvh2.h"
#include "bvh/scene_bvh4.h"
#include "incoherent_batch.h"
#include "line_aligned_vector.h"
#include "kernels/scene/scene.h"
#include "ray_sets.h"
#ifdef PT_HAVE_EMBREE
#include "embree_tracer.h"
#endif

namespace pt::bench {

struct FixtureOptions {
  int width = 1024, height = 768;   ///< primary rays (multiples of 4)
  size_t brute_force_rays = 16384;  ///< brute force traces this prefix of each set
  size_t brute_force_max_triangles = 3000;
  bool captured = true;  ///< also the queues of a render (bounce_queues, shadow_queues)
  Bvh4Options bvh4;      ///< how the BVH4 under test is built
};

/// Traces the queues of set `set` that lie in rays [begin, end) (begin and end
/// are queue ends): closest hits into hits[begin, end) or, for an occlusion
/// set, 0 / 1 into blocked[begin, end).
using TraceFn = std::function<void(int set, size_t begin, size_t end, Hit* hits, uint8_t* blocked)>;

struct TracerEntry {
  std::string name;
  TraceFn trace;
  /// For tracers whose own output is not Hit records (the queue tracer's
  /// arrays): turns the last trace of rays [begin, end) of a set into Hit
  /// records, for validation only (outside the timed loop).
  std::function<void(int set, size_t begin, size_t end, Hit* hits)> collect{};
  size_t max_rays = SIZE_MAX;  ///< traces only this prefix of a set
  bool whole_set = false;      ///< called once per set inside the thread arena, never in chunks
};

/// Runs the tracer over rays [0, n) of set `set` on `threads` threads (chunks
/// of whole queues spread over the threads).
void run_tracer(const TracerEntry& t, const RaySet& rays, int set, size_t n, int threads, Hit* hits, uint8_t* blocked);

class SceneFixture {
 public:
  SceneFixture(std::string label, Scene scene, const FixtureOptions& options);
  ~SceneFixture();

  const std::string& label() const { return label_; }
  const Scene& scene() const { return scene_; }
  /// The sets, and the index of one by name (-1 when absent).
  const std::vector<RaySet>& sets() const { return sets_; }
  int set_index(const std::string& name) const;
  const std::vector<TracerEntry>& tracers() const { return tracers_; }
  const Bvh4BuildStats& bvh4_stats() const { return bvh4_->stats(); }

  /// Compares the tracer's answers on the whole set (or its prefix) with the
  /// oracle's; "" when they agree, else what differs. Cached per (tracer, set).
  const std::string& validate(const TracerEntry& t, int set);
  /// Inner nodes visited and triangles tested by the BVH4 over a whole set:
  /// ray by ray, or (queue) by the queue tracer (ray-node tests and
  /// ray-triangle tests).
  TraversalCounters bvh4_work(int set, bool watertight, bool queue) const;
  /// Rays that differed in the last validation of (tracer, set).
  size_t mismatches(const TracerEntry& t, int set) const;

 private:
  /// A TraceFn calling closest(ray, hit) or any(ray) -> bool per ray of the range.
  template <class Closest, class Any>
  TraceFn single_rays(Closest closest, Any any) const {
    return [this, closest, any](int set, size_t b, size_t e, Hit* hits, uint8_t* blocked) {
      const RaySet& s = sets_[set];
      if (s.occlusion)
        for (size_t i = b; i < e; ++i) blocked[i] = any(s.rays[i]);
      else
        for (size_t i = b; i < e; ++i) closest(s.rays[i], hits[i]);
    };
  }
  /// A TraceFn tracing each ray of the range on its own through `bvh`, with one
  /// call per range into the level's kernels.
  TraceFn each_ray(const SceneBvh4& bvh) const {
    return [this, &bvh](int set, size_t b, size_t e, Hit* hits, uint8_t* blocked) {
      const RaySet& s = sets_[set];
      std::span<const Ray> rays = std::span<const Ray>(s.rays).subspan(b, e - b);
      if (s.occlusion) bench_queries().occluded_each(bvh, rays, std::span<uint8_t>(blocked + b, e - b));
      else bench_queries().intersect_each(bvh, rays, std::span<Hit>(hits + b, e - b));
    };
  }
  void make_sets(const FixtureOptions& options);
  void add_tracers(const FixtureOptions& options);
  void add_queue_tracer();
  void add_reference_tracers(const FixtureOptions& options);
#ifdef PT_HAVE_EMBREE
  void add_embree_tracers();
#endif
  /// Rays [begin, end) of a set as arrays, for the queue tracer.
  RayArrays arrays(int set, size_t begin, size_t end) const;

  std::string label_;
  Scene scene_;
  std::vector<RaySet> sets_;
  std::vector<std::array<LineAlignedVector<float>, 8>> arrays_;      ///< per set: ox, oy, oz, tmin, dx, dy, dz, tmax
  std::vector<std::array<LineAlignedVector<float>, 3>> queue_hits_;  ///< per set: the queue tracer's t, u, v
  std::vector<LineAlignedVector<uint32_t>> queue_prims_;             ///< and its primitives
  std::vector<std::vector<Hit>> oracle_hits_;
  std::vector<std::vector<uint8_t>> oracle_blocked_;
  std::unique_ptr<SceneBvh4> bvh4_;
  std::unique_ptr<WatertightBvh4> bvh4_watertight_;
  std::unique_ptr<IncoherentBatches> incoherent_;
  std::unique_ptr<SceneBvh2> bvh2_, brute_;
#ifdef PT_HAVE_EMBREE
  std::unique_ptr<EmbreeTracer> embree_high_, embree_default_;
  std::vector<EmbreeRays> embree_rays_;
#endif
  std::vector<TracerEntry> tracers_;
  std::map<std::pair<std::string, int>, std::pair<std::string, size_t>> validated_;
};

}  // namespace pt::bench
