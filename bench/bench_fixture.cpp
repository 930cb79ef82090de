// SceneFixture: ray sets, oracle answers, the tracer table and validation.
#include "bench_fixture.h"

#include <cmath>

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

}  // namespace

void run_tracer(const TracerEntry& t, RayKind kind, size_t n, int threads, Hit* hits, uint8_t* blocked) {
  if (t.whole_set) arena_of(threads).execute([&] { t.trace(kind, 0, n, hits, blocked); });
  else run_chunks(n, threads, [&](size_t b, size_t e) { t.trace(kind, b, e, hits, blocked); });
}

SceneFixture::SceneFixture(std::string label, Scene scene, const FixtureOptions& options)
    : label_(std::move(label)), scene_(std::move(scene)) {
  bvh4_ = std::make_unique<SceneBvh4>(scene_, options.bvh4);
  sets_[0] = primary_rays(scene_, options.width, options.height);
  std::vector<Hit> first(sets_[0].rays.size());
  run_chunks(first.size(), 2, [&](size_t b, size_t e) {
    for (size_t i = b; i < e; ++i) bvh4_->intersect(sets_[0].rays[i], first[i]);
  });
  sets_[1] = {RayKind::kDiffuse, diffuse_rays(scene_, sets_[0].rays, first, 1, /*shuffle=*/true)};
  sets_[2] = {RayKind::kShadow, shadow_rays(scene_, sets_[0].rays, first, 2, /*shuffle=*/true)};
  bvh2_ = std::make_unique<SceneBvh2>(scene_, Bvh2Mode::kMidpoint);
  for (int k = 0; k < 3; ++k) {
    const std::vector<Ray>& rays = sets_[k].rays;
    oracle_hits_[k].resize(rays.size());
    oracle_blocked_[k].resize(rays.size());
    run_chunks(rays.size(), 2, [&](size_t b, size_t e) {
      uint64_t tests = 0;
      for (size_t i = b; i < e; ++i) {
        if (sets_[k].occlusion()) oracle_blocked_[k][i] = bvh2_->occluded(rays[i], tests);
        else bvh2_->intersect(rays[i], oracle_hits_[k][i], tests);
      }
    });
  }
  add_tracers(options);
}

SceneFixture::~SceneFixture() = default;

void SceneFixture::add_tracers(const FixtureOptions& options) {
  tracers_.push_back({"bvh4", each_ray(*bvh4_)});
  TracerEntry packets{"bvh4_packet", [this](RayKind kind, size_t b, size_t e, Hit* hits, uint8_t*) {
                        bvh4_->intersect(std::span<const Ray>(sets_[int(kind)].rays).subspan(b, e - b),
                                         std::span<Hit>(hits + b, e - b));
                      }};
  packets.primary_only = true;
  tracers_.push_back(packets);
  incoherent_ = std::make_unique<IncoherentBatches>(*bvh4_, scene_);
  TracerEntry incoherent{"bvh4_incoherent", [this](RayKind kind, size_t b, size_t e, Hit* hits, uint8_t* blocked) {
                           std::span<const Ray> rays = std::span<const Ray>(sets_[int(kind)].rays).subspan(b, e - b);
                           if (kind == RayKind::kShadow)
                             incoherent_->occluded(rays, std::span<uint8_t>(blocked + b, e - b));
                           else incoherent_->intersect(rays, std::span<Hit>(hits + b, e - b));
                         }};
  incoherent.whole_set = true;
  tracers_.push_back(incoherent);
  Bvh4Options watertight;
  watertight.watertight = true;
  bvh4_watertight_ = std::make_unique<SceneBvh4>(scene_, watertight);
  tracers_.push_back({"bvh4_watertight", each_ray(*bvh4_watertight_)});
  add_reference_tracers(options);
#ifdef PT_HAVE_EMBREE
  add_embree_tracers();
#endif
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
  for (int k = 0; k < 3; ++k) embree_rays_[k] = convert_rays(sets_[k].rays, k == 0);
  embree_high_ = std::make_unique<EmbreeTracer>(scene_, RTC_BUILD_QUALITY_HIGH);
  embree_default_ = std::make_unique<EmbreeTracer>(scene_, RTC_BUILD_QUALITY_MEDIUM);
  for (auto [name, tracer] :
       {std::pair{"embree_high", embree_high_.get()}, {"embree_default", embree_default_.get()}}) {
    EmbreeTracer* t = tracer;
    tracers_.push_back(
        {std::string(name) + "_single", [this, t](RayKind kind, size_t b, size_t e, Hit* hits, uint8_t* blocked) {
           if (kind == RayKind::kShadow) t->occluded1(embree_rays_[int(kind)], b, e, blocked);
           else t->intersect1(embree_rays_[int(kind)], b, e, hits);
         }});
  }
  for (int width : {4, 8, 16}) {
    EmbreeTracer* t = embree_high_.get();
    TracerEntry e{"embree_high_packet" + std::to_string(width),
                  [this, t, width](RayKind kind, size_t b, size_t e, Hit* hits, uint8_t*) {
                    t->intersect_packets(embree_rays_[int(kind)], width, b, e, hits);
                  }};
    e.primary_only = true;
    tracers_.push_back(e);
  }
}
#endif

const std::string& SceneFixture::validate(const TracerEntry& t, RayKind kind) {
  auto key = std::pair{t.name, int(kind)};
  if (auto it = validated_.find(key); it != validated_.end()) return it->second.first;
  const std::vector<Ray>& rays = sets_[int(kind)].rays;
  size_t n = std::min(rays.size(), t.max_rays);
  std::vector<Hit> hits(n);
  std::vector<uint8_t> blocked(n);
  run_tracer(t, kind, n, 2, hits.data(), blocked.data());
  size_t bad = 0;
  float scale = std::max(max_component(abs(scene_.bounds.lower)), max_component(abs(scene_.bounds.upper)));
  for (size_t i = 0; i < n; ++i)
    bad += kind == RayKind::kShadow ? blocked[i] != oracle_blocked_[int(kind)][i]
                                    : !same_hit(oracle_hits_[int(kind)][i], hits[i], scale);
  std::string error;
  if (bad > allowed_mismatches(n))
    error = t.name + " disagrees with the reference BVH on " + std::to_string(bad) + " of " + std::to_string(n) + " " +
            ray_kind_name(kind) + " rays of " + label_;
  return (validated_[key] = {error, bad}).first;
}

TraversalCounters SceneFixture::bvh4_work(RayKind kind, bool watertight) const {
  const SceneBvh4& bvh = watertight ? *bvh4_watertight_ : *bvh4_;
  TraversalCounters c;
  for (const Ray& r : sets_[int(kind)].rays) {
    Hit h;
    if (kind == RayKind::kShadow) bvh.occluded(r, c);
    else bvh.intersect(r, h, c);
  }
  return c;
}

size_t SceneFixture::mismatches(const TracerEntry& t, RayKind kind) const {
  auto it = validated_.find({t.name, int(kind)});
  return it == validated_.end() ? 0 : it->second.second;
}

}  // namespace pt::bench
