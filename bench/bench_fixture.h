// One benchmark scene with everything its timings need: the triangles, the
// three ray sets, the oracle's answers (the reference binary BVH, whose
// triangle test is the brute-force one), and every tracer under test behind
// one chunked interface, each validated ray by ray before it is timed.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "bvh/scene_bvh4.h"
#include "kernels/scene/scene.h"
#include "incoherent_batch.h"
#include "ray_sets.h"
#include "bvh/scene_bvh2.h"
#ifdef PT_HAVE_EMBREE
#include "embree_tracer.h"
#endif

namespace pt::bench {

struct FixtureOptions {
  int width = 1024, height = 768;   ///< primary rays (multiples of 4)
  size_t brute_force_rays = 16384;  ///< brute force traces this prefix of each set
  size_t brute_force_max_triangles = 3000;
  Bvh4Options bvh4;  ///< how the BVH4 under test is built
};

/// Traces rays [begin, end) of a ray set: closest hits into `hits` or, for the
/// shadow set, occlusion into `blocked`.
using TraceFn = std::function<void(RayKind kind, size_t begin, size_t end, Hit* hits, uint8_t* blocked)>;

struct TracerEntry {
  std::string name;
  TraceFn trace;
  bool primary_only = false;   ///< packet APIs: coherent rays only
  size_t max_rays = SIZE_MAX;  ///< traces only this prefix of a set
  bool whole_set = false;      ///< called once per set inside the thread arena, never in chunks
};

/// Runs the tracer over rays [0, n) of a set on `threads` threads.
void run_tracer(const TracerEntry& t, RayKind kind, size_t n, int threads, Hit* hits, uint8_t* blocked);

class SceneFixture {
 public:
  SceneFixture(std::string label, Scene scene, const FixtureOptions& options);
  ~SceneFixture();

  const std::string& label() const { return label_; }
  const Scene& scene() const { return scene_; }
  const RaySet& rays(RayKind k) const { return sets_[int(k)]; }
  const std::vector<TracerEntry>& tracers() const { return tracers_; }
  const Bvh4BuildStats& bvh4_stats() const { return bvh4_->stats(); }

  /// Compares the tracer's answers on the whole set (or its prefix) with the
  /// oracle's; "" when they agree, else what differs. Cached per (tracer, kind).
  const std::string& validate(const TracerEntry& t, RayKind kind);
  /// Inner nodes visited and triangles tested by the BVH4 over a whole set.
  TraversalCounters bvh4_work(RayKind kind, bool watertight) const;
  /// Rays that differed in the last validation of (tracer, kind).
  size_t mismatches(const TracerEntry& t, RayKind kind) const;

 private:
  /// A TraceFn calling closest(ray, hit) or any(ray) -> bool per ray of the range.
  template <class Closest, class Any>
  TraceFn single_rays(Closest closest, Any any) const {
    return [this, closest, any](RayKind kind, size_t b, size_t e, Hit* hits, uint8_t* blocked) {
      const std::vector<Ray>& rays = sets_[int(kind)].rays;
      if (kind == RayKind::kShadow)
        for (size_t i = b; i < e; ++i) blocked[i] = any(rays[i]);
      else
        for (size_t i = b; i < e; ++i) closest(rays[i], hits[i]);
    };
  }
  /// A TraceFn tracing each ray of the range on its own through `bvh`, with one
  /// call per range into the level's kernels.
  TraceFn each_ray(const SceneBvh4& bvh) const {
    return [this, &bvh](RayKind kind, size_t b, size_t e, Hit* hits, uint8_t* blocked) {
      std::span<const Ray> rays = std::span<const Ray>(sets_[int(kind)].rays).subspan(b, e - b);
      if (kind == RayKind::kShadow) bvh.occluded_each(rays, std::span<uint8_t>(blocked + b, e - b));
      else bvh.intersect_each(rays, std::span<Hit>(hits + b, e - b));
    };
  }
  void add_tracers(const FixtureOptions& options);
  void add_reference_tracers(const FixtureOptions& options);
#ifdef PT_HAVE_EMBREE
  void add_embree_tracers();
#endif

  std::string label_;
  Scene scene_;
  RaySet sets_[3];
  std::vector<Hit> oracle_hits_[3];
  std::vector<uint8_t> oracle_blocked_[3];
  std::unique_ptr<SceneBvh4> bvh4_, bvh4_watertight_;
  std::unique_ptr<IncoherentBatches> incoherent_;
  std::unique_ptr<SceneBvh2> bvh2_, brute_;
#ifdef PT_HAVE_EMBREE
  std::unique_ptr<EmbreeTracer> embree_high_, embree_default_;
  EmbreeRays embree_rays_[3];
#endif
  std::vector<TracerEntry> tracers_;
  std::map<std::pair<std::string, int>, std::pair<std::string, size_t>> validated_;
};

}  // namespace pt::bench
