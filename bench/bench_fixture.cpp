// SceneFixture: ray sets, oracle answers, the tracer table and validation.
#include "bench_fixture.h"

#include <cmath>

#include <oneapi/tbb/enumerable_thread_specific.h>

#include "captured_queues.h"
#include "ray_driver.h"

namespace pt::bench {
namespace {

/// Same closest hit: both misses; the same primitive at nearly the same t (the
/// triangle tests round differently); or an exact tie (same t within 1e-6).
bool same_hit(const Hit& e, const Hit& a, float scale) {
  if (!e.valid() || !a.valid()) return e.valid() == a.valid();
  float t = std::max(std::fabs(e.t), std::fabs(a.t));
  if (e.prim == a.prim) return std::fabs(e.t - a.t) <= 1e-5f * std::max(t, scale);
  return std::fabs(e.t - a.t) <= 1e-6f * t;
}

/// Rays that may disagree by rounding (rays through shared edges, where
/// non-watertight tests let a ray through or not by their last bit): 1 in
/// 10000, at least 2. Every tracer's count is reported.
size_t allowed_mismatches(size_t n) { return std::max<size_t>(2, n / 10000); }

/// The queue tracer's outputs on one thread.
struct QueueOutputs {
  QueueScratch scratch;
  std::vector<float> t, u, v;
  std::vector<uint32_t> prim;
};

}  // namespace

void run_tracer(const TracerEntry& t, const RaySet& rays, int set, size_t n, int threads, Hit* hits, uint8_t* blocked) {
  if (t.whole_set) arena_of(threads).execute([&] { t.trace(set, 0, n, hits, blocked); });
  else run_queues(rays.queue_ends, n, threads, [&](size_t b, size_t e) { t.trace(set, b, e, hits, blocked); });
}

SceneFixture::SceneFixture(std::string label, Scene scene, const FixtureOptions& options)
    : label_(std::move(label)), scene_(std::move(scene)) {
  bvh4_ = std::make_unique<SceneBvh4>(scene_, options.bvh4);
  make_sets(options);
  bvh2_ = std::make_unique<SceneBvh2>(scene_, Bvh2Mode::kMidpoint);
  oracle_hits_.resize(sets_.size());
  oracle_blocked_.resize(sets_.size());
  for (size_t k = 0; k < sets_.size(); ++k) {
    const std::vector<Ray>& rays = sets_[k].rays;
    oracle_hits_[k].resize(rays.size());
    oracle_blocked_[k].resize(rays.size());
    run_chunks(rays.size(), 2, [&](size_t b, size_t e) {
      uint64_t tests = 0;
      for (size_t i = b; i < e; ++i) {
        if (sets_[k].occlusion) oracle_blocked_[k][i] = bvh2_->occluded(rays[i], tests);
        else bvh2_->intersect(rays[i], oracle_hits_[k][i], tests);
      }
    });
  }
  add_tracers(options);
}

SceneFixture::~SceneFixture() = default;

void SceneFixture::make_sets(const FixtureOptions& options) {
  sets_.push_back(primary_rays(scene_, options.width, options.height));
  const std::vector<Ray>& primary = sets_[0].rays;
  std::vector<Hit> first(primary.size());
  run_chunks(first.size(), 2, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) bvh4_->intersect(primary[i], first[i]);
  });
  sets_.push_back(ray_set("diffuse", false, diffuse_rays(scene_, primary, first, 1)));
  sets_.push_back(ray_set("shadow", true, shadow_rays(scene_, primary, first, 2)));
  sets_.push_back(ray_set("diffuse_shuffled", false, diffuse_rays(scene_, primary, first, 1, /*shuffle=*/true)));
  sets_.push_back(ray_set("shadow_shuffled", true, shadow_rays(scene_, primary, first, 2, /*shuffle=*/true)));
  if (options.captured) {
    CapturedQueues q = capture_queues(scene_, *bvh4_);
    sets_.push_back(std::move(q.bounce));
    sets_.push_back(std::move(q.shadow));
  }
}

int SceneFixture::set_index(const std::string& name) const {
  for (size_t k = 0; k < sets_.size(); ++k)
    if (sets_[k].name == name) return static_cast<int>(k);
  return -1;
}

RayArrays SceneFixture::arrays(int set, size_t b, size_t e) const {
  const std::array<LineAlignedVector<float>, 8>& a = arrays_[set];
  RayArrays r;
  for (int k = 0; k < 3; ++k) {
    r.org[k] = a[k].data() + b;
    r.dir[k] = a[4 + k].data() + b;
  }
  r.tmin = a[3].data() + b;
  r.tmax = a[7].data() + b;
  r.size = e - b;
  return r;
}

void SceneFixture::add_tracers(const FixtureOptions& options) {
  tracers_.push_back({"bvh4", each_ray(*bvh4_)});
  add_queue_tracer();
  incoherent_ = std::make_unique<IncoherentBatches>(*bvh4_, scene_);
  TracerEntry incoherent{"bvh4_incoherent", [this](int set, size_t b, size_t e, Hit* hits, uint8_t* blocked) {
                           std::span<const Ray> rays = std::span<const Ray>(sets_[set].rays).subspan(b, e - b);
                           if (sets_[set].occlusion)
                             incoherent_->occluded(rays, std::span<uint8_t>(blocked + b, e - b));
                           else incoherent_->intersect(rays, std::span<Hit>(hits + b, e - b));
                         }};
  incoherent.whole_set = true;
  tracers_.push_back(incoherent);
  bvh4_watertight_ = std::make_unique<WatertightBvh4>(scene_, options.bvh4);
  tracers_.push_back(
      {"bvh4_watertight", single_rays([this](const Ray& r, Hit& h) { bvh4_watertight_->intersect(r, h); },
                                      [this](const Ray& r) { return bvh4_watertight_->occluded(r); })});
  add_reference_tracers(options);
#ifdef PT_HAVE_EMBREE
  add_embree_tracers();
#endif
}

void SceneFixture::add_queue_tracer() {
  for (const RaySet& set : sets_) {
    std::array<LineAlignedVector<float>, 8>& a = arrays_.emplace_back();
    for (LineAlignedVector<float>& f : a) f.resize(set.rays.size());
    for (size_t i = 0; i < set.rays.size(); ++i) {
      const Ray& r = set.rays[i];
      const float f[8] = {r.org.x, r.org.y, r.org.z, r.tmin, r.dir.x, r.dir.y, r.dir.z, r.tmax};
      for (int j = 0; j < 8; ++j) a[j][i] = f[j];
    }
  }
  // The queue tracer writes its hits as arrays (its output): into the set's
  // arrays, which become Hit records only for validation.
  for (const RaySet& set : sets_) {
    std::array<LineAlignedVector<float>, 3>& h = queue_hits_.emplace_back();
    for (LineAlignedVector<float>& f : h) f.resize(set.rays.size());
    queue_prims_.emplace_back(set.rays.size());
  }
  auto scratch = std::make_shared<tbb::enumerable_thread_specific<QueueScratch>>();
  TracerEntry queue{
      "bvh4_queue", [this, scratch](int set, size_t b, size_t e, Hit*, uint8_t* blocked) {
        const RaySet& s = sets_[set];
        size_t qi = std::upper_bound(s.queue_ends.begin(), s.queue_ends.end(), b) - s.queue_ends.begin();
        for (size_t qb = b; qb < e; ++qi) {
          const size_t qe = std::min(e, s.queue_ends[qi]);
          const RayArrays rays = arrays(set, qb, qe);
          if (s.occlusion) {
            bvh4_->occluded_queue(rays, blocked + qb, scratch->local());
          } else {
            std::array<LineAlignedVector<float>, 3>& h = queue_hits_[set];
            bvh4_->intersect_queue(
                rays, HitArrays{h[0].data() + qb, h[1].data() + qb, h[2].data() + qb, queue_prims_[set].data() + qb},
                scratch->local());
          }
          qb = qe;
        }
      }};
  queue.collect = [this](int set, size_t b, size_t e, Hit* hits) {
    const std::array<LineAlignedVector<float>, 3>& h = queue_hits_[set];
    for (size_t i = b; i < e; ++i) hits[i] = Hit{h[0][i], h[1][i], h[2][i], queue_prims_[set][i]};
  };
  tracers_.push_back(queue);
}

void SceneFixture::add_reference_tracers(const FixtureOptions& options) {
  tracers_.push_back({"bvh2_midpoint", single_rays(
                                           [this](const Ray& r, Hit& h) {
                                             uint64_t n = 0;
                                             bvh2_->intersect(r, h, n);
                                           },
                                           [this](const Ray& r) {
                                             uint64_t n = 0;
                                             return bvh2_->occluded(r, n);
                                           })});
  if (scene_.triangles.size() <= options.brute_force_max_triangles) {
    brute_ = std::make_unique<SceneBvh2>(scene_, Bvh2Mode::kBruteForce);
    TracerEntry e{"brute_force", single_rays(
                                     [this](const Ray& r, Hit& h) {
                                       uint64_t n = 0;
                                       brute_->intersect(r, h, n);
                                     },
                                     [this](const Ray& r) {
                                       uint64_t n = 0;
                                       return brute_->occluded(r, n);
                                     })};
    e.max_rays = options.brute_force_rays;
    tracers_.push_back(e);
  }
}

#ifdef PT_HAVE_EMBREE
void SceneFixture::add_embree_tracers() {
  for (const RaySet& set : sets_) embree_rays_.push_back(convert_rays(set));
  embree_high_ = std::make_unique<EmbreeTracer>(scene_, RTC_BUILD_QUALITY_HIGH);
  embree_default_ = std::make_unique<EmbreeTracer>(scene_, RTC_BUILD_QUALITY_MEDIUM);
  for (auto [name, tracer] :
       {std::pair{"embree_high", embree_high_.get()}, {"embree_default", embree_default_.get()}}) {
    for (EmbreeMethod m : kEmbreeMethods) {
      EmbreeTracer* t = tracer;
      tracers_.push_back({std::string(name) + "_" + embree_method_name(m),
                          [this, t, m](int set, size_t b, size_t e, Hit* hits, uint8_t* blocked) {
                            t->trace(m, embree_rays_[set], b, e, hits, blocked);
                          }});
    }
  }
}
#endif

const std::string& SceneFixture::validate(const TracerEntry& t, int set) {
  auto key = std::pair{t.name, set};
  if (auto it = validated_.find(key); it != validated_.end()) return it->second.first;
  const RaySet& s = sets_[set];
  size_t n = std::min(s.rays.size(), t.max_rays);
  std::vector<Hit> hits(n);
  std::vector<uint8_t> blocked(n);
  run_tracer(t, s, set, n, 2, hits.data(), blocked.data());
  if (t.collect && !s.occlusion) t.collect(set, 0, n, hits.data());
  size_t bad = 0;
  float scale = std::max(max_component(abs(scene_.bounds.lower)), max_component(abs(scene_.bounds.upper)));
  for (size_t i = 0; i < n; ++i)
    bad += s.occlusion ? blocked[i] != oracle_blocked_[set][i] : !same_hit(oracle_hits_[set][i], hits[i], scale);
  std::string error;
  if (bad > allowed_mismatches(n))
    error = t.name + " disagrees with the reference BVH on " + std::to_string(bad) + " of " + std::to_string(n) + " " +
            s.name + " rays of " + label_;
  return (validated_[key] = {error, bad}).first;
}

TraversalCounters SceneFixture::bvh4_work(int set, bool watertight, bool queue) const {
  const RaySet& s = sets_[set];
  TraversalCounters c;
  if (queue) {
    QueueOutputs q;
    std::vector<uint8_t> blocked(s.rays.size());
    size_t b = 0;
    for (size_t e : s.queue_ends) {
      const size_t n = e - b;
      q.t.resize(n), q.u.resize(n), q.v.resize(n), q.prim.resize(n);
      if (s.occlusion) bvh4_->occluded_queue(arrays(set, b, e), blocked.data() + b, q.scratch, &c);
      else
        bvh4_->intersect_queue(arrays(set, b, e), HitArrays{q.t.data(), q.u.data(), q.v.data(), q.prim.data()},
                               q.scratch, &c);
      b = e;
    }
    return c;
  }
  for (const Ray& r : s.rays) {
    Hit h;
    if (s.occlusion) watertight ? bvh4_watertight_->occluded(r, &c) : bvh4_->occluded(r, &c);
    else watertight ? bvh4_watertight_->intersect(r, h, &c) : bvh4_->intersect(r, h, &c);
  }
  return c;
}

size_t SceneFixture::mismatches(const TracerEntry& t, int set) const {
  auto it = validated_.find({t.name, set});
  return it == validated_.end() ? 0 : it->second.second;
}

}  // namespace pt::bench
