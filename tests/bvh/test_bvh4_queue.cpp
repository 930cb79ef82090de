// The queue tracer (SceneBvh4::intersect_queue / occluded_queue, queue_coherence.h)
// at the instruction-set level in use, against the single-ray queries, ray by
// ray and bit for bit: the same t, u, v and primitive for every ray, except
// that of two different triangles at exactly the same t either may be
// reported (counted, and required to be rare); the same occlusion answer for
// every shadow ray. Every queue length around the lane width and the stream's
// part size; coherent, incoherent and shuffled rays; rays with tmin > 0;
// untraceable rays; spheres; a tree deep enough that lists thin out and go
// on ray by ray; the interleaved walks against the single-ray walks from the
// same node; any-hit parts of at most 64 rays, traced as one masked set;
// coherent queues traced as sets of 64 rays under a frustum, where it is
// tightest, and across direction octants; sky-like any-hit queues with every
// edge case of the slab constants, counted or not; nothing written past a
// queue.
#include <algorithm>
#include <array>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "bvh/bvh4_interleaved.h"
#include "bvh/queue_coherence.h"
#include "bvh/scene_bvh4.h"
#include "kernels/simd/cache_size.h"
#include "support/bvh4_support.h"
#include "support/test_support.h"

namespace pt::test {
namespace {

const Hit kSentinel = kSentinelHit;

/// Rays a stream traces in one part at every level (bvh4_stream.h).
constexpr size_t kPartRays = 4096;

size_t lanes() { return isa_lanes(active_isa()); }

/// Gives every `stride`-th ray a tmin uniform in [0, 1.5) (seeded), so that
/// it starts past its origin.
void start_past_origin(std::vector<Ray>& rays, size_t stride, uint32_t seed) {
  std::mt19937 rng(seed);
  for (size_t i = 0; i < rays.size(); i += stride)
    rays[i].tmin = std::uniform_real_distribution<float>(0.0f, 1.5f)(rng);
}

Scene built_in_scene() { return load_collada_file(project_scene("cornell_spheres.dae")).scene; }

using Queue = QueueArrays;

bool same_bits(const Hit& a, const Hit& b) { return std::memcmp(&a, &b, sizeof(Hit)) == 0; }

/// Traces `rays` as one queue, closest hit and any hit, and compares every
/// ray with the single-ray queries. Returns the number of exact ties
/// reported as the other triangle. `scratch` is reused across calls, as a
/// render reuses it.
size_t expect_queue_matches_single_rays(const SceneBvh4& bvh, std::span<const Ray> rays, QueueScratch& scratch,
                                        const std::string& what) {
  Queue q(rays);
  bvh.intersect_queue(q.rays(), q.hits(), scratch);
  bvh.occluded_queue(q.rays(), q.blocked.data(), scratch);
  size_t ties = 0, bad = 0;
  for (size_t i = 0; i < rays.size() && bad < 10; ++i) {
    Hit single;
    bvh.intersect(rays[i], single);
    const Hit got = q.hit(i);
    if (single.prim != got.prim && single.valid() && got.valid() && single.t == got.t) {
      ++ties;  // two triangles at exactly the same t: either is the closest hit
    } else if (!same_bits(single, got)) {
      ++bad;
      ADD_FAILURE() << what << ": ray " << i << " got t " << got.t << " prim " << got.prim << ", alone t " << single.t
                    << " prim " << single.prim;
    }
    const bool blocked = bvh.occluded(rays[i]);
    if (q.blocked[i] != uint8_t(blocked)) {
      ++bad;
      ADD_FAILURE() << what << ": ray " << i << " blocked " << int(q.blocked[i]) << ", alone " << blocked;
    }
  }
  EXPECT_TRUE(same_bits(q.hit(rays.size()), kSentinel)) << what << ": wrote past the queue";
  EXPECT_EQ(q.blocked[rays.size()], kUnwritten) << what << ": wrote past the queue";
  return ties;
}

/// Rays of every kind over a scene: camera rays (coherent), diffuse and
/// shadow rays from their hits in the camera rays' order and shuffled, and
/// uniformly random rays (mixed direction signs, from anywhere).
std::vector<std::pair<std::string, std::vector<Ray>>> ray_kinds(const Scene& s, const SceneBvh4& bvh, int w, int h) {
  std::vector<Ray> camera = camera_rays(s, w, h);
  std::vector<Hit> first(camera.size());
  for (size_t i = 0; i < camera.size(); ++i) bvh.intersect(camera[i], first[i]);
  return {{"camera", camera},
          {"diffuse", diffuse_rays(s, camera, first, 3)},
          {"shadow", shadow_rays(s, camera, first, 4)},
          {"diffuse shuffled", diffuse_rays(s, camera, first, 3, true)},
          {"shadow shuffled", shadow_rays(s, camera, first, 4, true)},
          {"random", uniform_random_rays(s, 3000, 5)}};
}

void expect_every_kind_matches(const Scene& s, const std::string& name, int w, int h) {
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  size_t ties = 0, total = 0;
  for (const auto& [kind, rays] : ray_kinds(s, bvh, w, h)) {
    ties += expect_queue_matches_single_rays(bvh, rays, scratch, name + ", " + kind);
    total += rays.size();
  }
  EXPECT_LE(ties, std::max<size_t>(2, total / 10000)) << name << ": " << ties << " exact ties of " << total;
}

TEST(Bvh4Queue, EveryRayKindMatchesSingleRaysBitForBit) {
  expect_every_kind_matches(built_in_scene(), "built-in Cornell box", 64, 48);  // spheres too
  expect_every_kind_matches(tessellated_sphere(5, {0, 0, 0}, 1.0f), "tessellated sphere", 64, 48);
}

TEST(Bvh4Queue, SharedScenesMatchSingleRaysBitForBit) {
  PT_REQUIRE_SHARED_SCENES();
  for (const char* name : {"CBbunny.dae", "CBgems.dae", "teapot.dae"})
    expect_every_kind_matches(load_collada_file(shared_scene(name)).scene, name, 96, 72);
}

TEST(Bvh4Queue, CameraQueuesInPixelOrderMatchSingleRays) {
  // A pinhole camera's queue as the wavefront makes it: every pixel's samples
  // one after the other (one origin, nearly one direction per run of K rays),
  // which the queue tracer traces as coherent sets.
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  std::vector<Ray> pixels = camera_rays(s, 32, 24), rays;
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> jitter(-1e-3f, 1e-3f);
  for (const Ray& p : pixels)
    for (int k = 0; k < 16; ++k)
      rays.push_back({p.org, p.tmin, p.dir + float3{jitter(rng), jitter(rng), 0.0f}, p.tmax});
  size_t ties = expect_queue_matches_single_rays(bvh, rays, scratch, "camera rays in pixel order");
  EXPECT_LE(ties, 2u);
}

TEST(Bvh4Queue, CoherentSetsAcrossDirectionOctantsMatchSingleRays) {
  // A camera looking straight down an axis: its rays change the sign of two
  // direction components at the middle of the image, so the sets there hold
  // rays of two or four octants, each traced as a set of its own. Whole
  // rows of 64 pixels form each set.
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  const float3 eye = s.bounds.center() + float3{0.0f, 0.0f, 0.5f * length(s.bounds.upper - s.bounds.lower)};
  std::vector<Ray> rays;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      rays.push_back({eye, 0.0f, {(x - 31.5f) / 512.0f, (y - 31.5f) / 512.0f, -1.0f}, kInfinity});
  const Queue q(rays);
  ASSERT_TRUE(in_coherent_runs(q.rays(), kCoherentSpread * scene_extent(bvh.bvh()), lanes()));  // traced as sets
  size_t mixed = 0;
  for (size_t set = 0; set < rays.size(); set += 64)
    mixed += std::signbit(rays[set].dir.x) != std::signbit(rays[set + 63].dir.x);
  EXPECT_EQ(mixed, 64u);  // every row crosses x = 0
  EXPECT_EQ(expect_queue_matches_single_rays(bvh, rays, scratch, "camera across octants"), 0u);
}

TEST(Bvh4Queue, DirectionalShadowQueuesInPixelOrderGoAsSetsAndMatchSingleRays) {
  // The shadow rays of a directional light from the first hits of a queue in
  // pixel order: every pixel's 16 samples hit nearly one point and leave in
  // one direction, so the queue is coherent at every lane width (traced as
  // coherent sets); shuffled, it is not (a stream). Spheres are tested too.
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  const std::vector<Ray> pixels = camera_rays(s, 32, 24);
  const float3 to_light = normalize(float3{0.3f, 1.0f, 0.2f});
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> jitter(-1e-4f, 1e-4f);
  std::vector<Ray> rays;
  for (const Ray& p : pixels) {
    Hit h;
    if (!bvh.intersect(p, h)) continue;
    const float3 at = p.org + p.dir * (h.t * 0.999f);
    for (int k = 0; k < 16; ++k)
      rays.push_back({at + float3{jitter(rng), jitter(rng), jitter(rng)}, 0.0f, to_light, kInfinity});
  }
  ASSERT_GE(rays.size(), 4 * lanes());
  const float near = kCoherentSpread * scene_extent(bvh.bvh());
  Queue q(rays);
  EXPECT_TRUE(in_coherent_runs(q.rays(), near, lanes()));
  size_t ties = expect_queue_matches_single_rays(bvh, rays, scratch, "directional shadow rays in pixel order");
  std::shuffle(rays.begin(), rays.end(), rng);
  EXPECT_FALSE(in_coherent_runs(Queue(rays).rays(), near, lanes()));
  ties += expect_queue_matches_single_rays(bvh, rays, scratch, "directional shadow rays shuffled");
  EXPECT_LE(ties, 2u);
}

/// A scene of the one-direction tests, and whether its camera sees it (the
/// built-in scene) or probes from all around do (a tessellated sphere at the
/// origin).
struct OneDirectionScene {
  Scene scene;
  bool camera_view;
};

/// The built-in scene (a few leaves, spheres) and a tessellated sphere
/// (20,480 triangles: many leaves, each with its own direction terms), which
/// half of the rays leave through.
std::vector<OneDirectionScene> one_direction_scenes() {
  std::vector<OneDirectionScene> scenes;
  scenes.push_back({built_in_scene(), true});
  scenes.push_back({tessellated_sphere(5, {0, 0, 0}, 1.0f), false});
  return scenes;
}

/// A directional light's shadow rays over `bvh`: from points just off the
/// scene's surfaces (the hits of its camera view, or of probes from all
/// around it), `per_point` rays each (jittered by 1e-4 around the point, so
/// that runs of them are coherent). In the built-in scene, a closed box,
/// they end at a quarter of the scene's extent, so that some get through.
std::vector<Ray> directional_shadow_rays(const OneDirectionScene& c, const SceneBvh4& bvh, float3 to_light,
                                         int per_point) {
  std::vector<Ray> rays;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> jitter(-1e-4f, 1e-4f);
  const float tmax = c.camera_view ? 0.25f * scene_extent(bvh.bvh()) : kInfinity;
  auto add = [&](const Ray& probe) {
    Hit h;
    if (!bvh.intersect(probe, h)) return;
    const float3 at = probe.org + probe.dir * (h.t * 0.999f);
    for (int k = 0; k < per_point; ++k)
      rays.push_back({at + float3{jitter(rng), jitter(rng), jitter(rng)}, 0.0f, to_light, tmax});
  };
  if (c.camera_view) {
    for (const Ray& p : camera_rays(c.scene, 40, 30)) add(p);
    return rays;
  }
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (int i = 0; i < 1500; ++i) {
    const float3 from = normalize(float3{unit(rng), unit(rng), unit(rng)}) * 3.0f;
    add({from, 0.0f, normalize(float3{unit(rng), unit(rng), unit(rng)} * 0.3f - from), kInfinity});
  }
  return rays;
}

TEST(Bvh4Queue, DirectionalSetsMatchSingleRaysAlsoWithOneRayOfAnotherDirection) {
  // A coherent set whose rays all leave in one direction tests each leaf
  // triangle's share of the direction once for all of them. Then one ray of
  // each set (alternately the first and a later one) turned by about a
  // degree, still coherent, must keep the set from that path, or that ray's
  // answers go wrong.
  const float3 to_light = normalize(float3{0.3f, 1.0f, 0.2f});
  const float3 turned = normalize(float3{0.32f, 1.0f, 0.2f});
  for (const OneDirectionScene& c : one_direction_scenes()) {
    SceneBvh4 bvh(c.scene);
    QueueScratch scratch;
    std::vector<Ray> rays = directional_shadow_rays(c, bvh, to_light, 16);
    ASSERT_GE(rays.size(), 64 * lanes());
    const float near = kCoherentSpread * scene_extent(bvh.bvh());
    EXPECT_TRUE(in_coherent_runs(Queue(rays).rays(), near, lanes()));
    size_t blocked = 0;
    for (const Ray& r : rays) blocked += bvh.occluded(r);
    EXPECT_GT(blocked, rays.size() / 10);  // both answers are exercised
    EXPECT_LT(blocked, rays.size() - rays.size() / 10);
    size_t ties = expect_queue_matches_single_rays(bvh, rays, scratch, "directional sets");
    for (size_t set = 0; set * 64 < rays.size(); ++set)
      rays[std::min(rays.size() - 1, set * 64 + (set % 2 ? 37 : 0))].dir = turned;
    EXPECT_TRUE(in_coherent_runs(Queue(rays).rays(), near, lanes()));
    ties += expect_queue_matches_single_rays(bvh, rays, scratch, "directional sets with one turned ray");
    EXPECT_LE(ties, 2u);
  }
}

TEST(Bvh4Queue, StreamsOfOneDirectionMatchSingleRaysAtEveryLength) {
  // A queue whose rays all leave in one direction but from scattered points
  // (a directional light's shadow rays from later vertices: shuffled, so not
  // coherent) goes as a stream whose leaves compute each triangle's share of
  // the direction once per visit: as one masked set up to 64 rays, as lists
  // past that, in parts of 4096. Then some rays of each queue turned away
  // from the light (into the surfaces they leave, where most are blocked),
  // or only its last ray (in the last part), which must take the queue off
  // that path. Such a queue's node tests take each axis's near and far plane
  // from the direction's signs: other directions too, with negative
  // components and with +0 and -0 ones (clamped to huge reciprocals of
  // either sign), at three lengths, then with tmin > 0 on half the rays
  // (lists that carry tmin past their unwritten reciprocal directions).
  const float3 to_light = normalize(float3{0.3f, 1.0f, 0.2f});
  const float3 other_lights[] = {normalize(float3{-0.5f, 1.0f, -0.3f}), normalize(float3{0.4f, -1.0f, -0.6f}),
                                 float3{0.0f, 1.0f, 0.0f}, float3{-0.0f, -1.0f, -0.0f}, float3{-0.0f, 0.0f, 1.0f}};
  for (const OneDirectionScene& c : one_direction_scenes()) {
    SceneBvh4 bvh(c.scene);
    QueueScratch scratch;
    size_t ties = 0;
    for (const float3& light : other_lights) {
      std::vector<Ray> rays = directional_shadow_rays(c, bvh, light, 4);
      std::mt19937 rng(12);
      std::shuffle(rays.begin(), rays.end(), rng);
      for (size_t n : {size_t(64), size_t(300), rays.size()}) {
        std::vector<Ray> q(rays.begin(), rays.begin() + std::min(n, rays.size()));
        EXPECT_FALSE(in_coherent_runs(Queue(q).rays(), kCoherentSpread * scene_extent(bvh.bvh()), lanes()));
        const std::string size = std::to_string(n) + " rays";
        ties += expect_queue_matches_single_rays(bvh, q, scratch, "another direction, " + size);
        for (size_t i = 0; i < q.size(); i += 2) q[i].tmin = 0.01f;  // lists and sets that carry tmin
        ties += expect_queue_matches_single_rays(bvh, q, scratch, "another direction with tmin, " + size);
      }
    }
    std::vector<Ray> rays = directional_shadow_rays(c, bvh, to_light, 8);
    std::mt19937 rng(11);
    std::shuffle(rays.begin(), rays.end(), rng);
    ASSERT_GE(rays.size(), 4096u + 500u);
    for (size_t n : {size_t(1), size_t(7), lanes() + 1, size_t(64), size_t(65), size_t(300), rays.size()}) {
      std::vector<Ray> q(rays.begin(), rays.begin() + n);
      EXPECT_FALSE(in_coherent_runs(Queue(q).rays(), kCoherentSpread * scene_extent(bvh.bvh()), lanes()));
      const std::string size = std::to_string(n) + " rays";
      ties += expect_queue_matches_single_rays(bvh, q, scratch, "one direction, " + size);
      if (n < 2) continue;
      std::vector<Ray> last_turned = q;
      last_turned.back().dir = -to_light;
      ties += expect_queue_matches_single_rays(bvh, last_turned, scratch, "the last ray turned, " + size);
      for (size_t i = n / 2; i < n; i += 16) q[i].dir = -to_light;
      ties += expect_queue_matches_single_rays(bvh, q, scratch, "some rays turned, " + size);
    }
    EXPECT_LE(ties, 4u);
  }
}

/// Pads `rays` with copies of its last ray to a whole number of sets, so that
/// the next group of rays starts a set of its own.
void pad_to_whole_sets(std::vector<Ray>& rays) {
  while (rays.size() % 64 != 0) rays.push_back(rays.back());
}

/// A coherent queue over scene `s` that also holds, each group in sets of
/// its own, the rays where a coherent set's frustum is tightest or breaks
/// down: a pixel's samples; the same with tmin > 0, finite tmax of many
/// lengths and untraceable rays among them; rays along an axis (zero
/// direction components, clamped to a huge reciprocal) from grids above the
/// scene and through its middle, all +0, all -0, and mixed (sets that do not
/// share an octant); a set whose reciprocal directions range from ordinary
/// to clamped; a directional light's shadow rays from the first hits; 13
/// rays past a whole number of sets. Each quarter of the queue starts with
/// two sets of pixel samples, so that the queue is judged coherent
/// (in_coherent_runs looks at the runs that start its quarters).
std::vector<Ray> coherent_queue_with_edge_cases(const Scene& s, const SceneBvh4& bvh) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> jitter(-1e-3f, 1e-3f);
  const std::vector<Ray> pixels = camera_rays(s, 12, 9);
  std::vector<Ray> samples;  // 16 per pixel: 1728 rays, 27 sets
  for (const Ray& p : pixels)
    for (int k = 0; k < 16; ++k)
      samples.push_back({p.org, p.tmin, p.dir + float3{jitter(rng), jitter(rng), 0.0f}, p.tmax});
  const float3 lo = s.bounds.lower, ext = s.bounds.extent();
  std::vector<Ray> group[4];
  group[0] = samples;
  std::vector<Ray> late(samples.begin(), samples.begin() + 320);
  start_past_origin(late, 3, 10);
  for (size_t i = 0; i < late.size(); i += 4) late[i].tmax = late[i].tmin + length(ext) * (0.4f + 0.05f * (i % 13));
  late[37].org.x = NAN;
  late[101].dir.y = INFINITY;
  late[150].tmin = late[150].tmax;
  group[0].insert(group[0].end(), late.begin(), late.end());
  for (int sign : {1, -1, 0})  // all +0, all -0, mixed
    for (int i = 0; i < 16; ++i)
      for (int j = 0; j < 8; ++j) {
        const float y = sign == -1 ? lo.y + 0.5f * ext.y : s.bounds.upper.y + 0.1f * ext.y;
        const float3 org{lo.x + ext.x * (i + 0.37f) / 16, y, lo.z + ext.z * (j + 0.61f) / 8};  // off diagonals
        const float zero = sign == -1 || (sign == 0 && (i + j) % 5 == 0) ? -0.0f : 0.0f;
        group[1].push_back({org, 0.0f, {zero, -1.0f, zero}, kInfinity});
      }
  for (int i = 0; i < 64; ++i)
    group[2].push_back(
        {{lo.x - 0.1f * ext.x, lo.y + ext.y * (i + 0.5f) / 64, lo.z + 0.43f * ext.z}, 0.0f, {1, 0, 0}, kInfinity});
  for (int i = 0; i < 64; ++i)  // rdir.x from about 3 to 1e18, one sign
    group[2].push_back({{lo.x + ext.x * 0.2f, lo.y + ext.y * (i + 0.5f) / 64, lo.z + ext.z * 0.3f},
                        0.0f,
                        {i % 2 ? 1e-20f : 0.3f, -0.2f, 1.0f},
                        kInfinity});
  const float3 to_light = normalize(float3{0.3f, 1.0f, 0.2f});
  for (const Ray& p : pixels) {
    Hit h;
    if (!bvh.intersect(p, h)) continue;
    const float3 at = p.org + p.dir * (h.t * 0.999f);
    for (int k = 0; k < 16; ++k)
      group[3].push_back({at + float3{jitter(rng), jitter(rng), jitter(rng)}, 0.0f, to_light, kInfinity});
  }
  size_t quarter = 0;
  for (std::vector<Ray>& g : group) {
    g.insert(g.begin(), samples.begin(), samples.begin() + 128);
    pad_to_whole_sets(g);
    quarter = std::max(quarter, g.size());
  }
  std::vector<Ray> rays;
  for (std::vector<Ray>& g : group) {
    for (size_t i = 0; g.size() < quarter; i = (i + 64) % samples.size())
      g.insert(g.end(), samples.begin() + i, samples.begin() + i + 64);
    rays.insert(rays.end(), g.begin(), g.end());
  }
  rays.insert(rays.end(), samples.begin(), samples.begin() + 13);
  return rays;
}

TEST(Bvh4Queue, CoherentSetsMatchSingleRaysWhereTheirFrustumIsTightest) {
  // A coherent queue goes as sets of 64 rays whose nodes are culled by the
  // set's frustum (bvh4_coherent_set.h), which must never drop a child that
  // one of its rays enters: near the world's origin (the built-in Cornell
  // box: axis-aligned walls, boxes of no thickness, spheres) and far from it
  // (a sphere mesh 2 units across, 2e4 from the origin), where the frustum's
  // widening against rounding matters most.
  const Scene scenes[] = {built_in_scene(), tessellated_sphere(4, {1e4f, -3e3f, 2e4f}, 2.0f)};
  for (const Scene& s : scenes) {
    SceneBvh4 bvh(s);
    QueueScratch scratch;
    const std::vector<Ray> rays = coherent_queue_with_edge_cases(s, bvh);
    EXPECT_TRUE(in_coherent_runs(Queue(rays).rays(), kCoherentSpread * scene_extent(bvh.bvh()), lanes()));
    const size_t ties = expect_queue_matches_single_rays(bvh, rays, scratch, "coherent sets");
    EXPECT_LE(ties, 2u);
  }
}

TEST(Bvh4Queue, SpheresAnswerInEveryLaneAsTheScalarTestDoes) {
  // The queue tracer tests spheres K rays at a time (streams and sets);
  // each lane must give the scalar test's bits where it is most fragile: rays
  // from inside, grazing rays, origins on the surface, tmin between the two
  // roots, tmax short of the first, directions far from unit length, huge and
  // tiny spheres, and untraceable rays, shuffled so that every kind shares
  // batches with the others.
  Scene s = built_in_scene();
  ASSERT_FALSE(s.spheres.empty());
  s.spheres.push_back({{0.0f, 0.0f, -2000.0f}, 1500.0f, s.spheres[0].material});
  s.spheres.push_back({{0.1f, 0.3f, 0.2f}, 1e-3f, s.spheres[0].material});
  SceneBvh4 bvh(s);
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f), share(0.0f, 1.0f);
  auto random_dir = [&] {
    for (;;) {
      float3 d{unit(rng), unit(rng), unit(rng)};
      if (dot(d, d) > 1e-4f && dot(d, d) <= 1.0f) return normalize(d);
    }
  };
  std::vector<Ray> rays;
  for (const Sphere& sp : s.spheres)
    for (int k = 0; k < 300; ++k) {
      const float3 n = random_dir(), d = random_dir();
      const float scale = std::array<float, 3>{1.0f, 1e-3f, 1e3f}[k % 3];
      rays.push_back({sp.center + n * (0.5f * sp.radius * share(rng)), 0.0f, d * scale, kInfinity});  // inside
      rays.push_back({sp.center + n * sp.radius, 0.0f, d, kInfinity});                                // on the surface
      // Grazing: aimed past the centre at the radius, within a few ulps either way.
      const float3 side = normalize(cross(n, random_dir()));
      const float3 far = sp.center + n * (3.0f * sp.radius + 1.0f);
      const float3 target = sp.center + side * (sp.radius * (1.0f + 4e-7f * unit(rng)));
      rays.push_back({far, 0.0f, (target - far) * scale, kInfinity});
      // Through the centre from outside, with tmin between the roots or tmax short of the first.
      const float3 from = sp.center + n * (2.0f * sp.radius + 0.5f);
      const float3 to_center = (sp.center - from) * scale;
      const float t_center = 1.0f;  // from + to_center * 1 is the centre
      rays.push_back({from, t_center * share(rng) * 1.5f, to_center, kInfinity});
      rays.push_back({from, 0.0f, to_center, t_center * share(rng)});
    }
  rays.push_back({{NAN, 0.0f, 0.0f}, 0.0f, {0.0f, 0.0f, 1.0f}, kInfinity});
  rays.push_back({{0.0f, 0.0f, 0.0f}, 1.0f, {0.0f, 0.0f, 1.0f}, 1.0f});
  std::shuffle(rays.begin(), rays.end(), rng);
  QueueScratch scratch;
  EXPECT_LE(expect_queue_matches_single_rays(bvh, rays, scratch, "sphere rays"), 2u);
}

TEST(Bvh4Queue, SceneExtentIsTheDiagonalOfTheSceneBounds) {
  // One triangle (a leaf as the root) and a tessellated sphere (an inner root).
  Scene one;
  one.positions = {{0, 0, 0}, {3, 0, 0}, {0, 4, 0}};
  one.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  one.triangles = {{0, 1, 2}};
  one.triangle_material = {0};
  one.materials.push_back(Material{});
  one.bounds = compute_scene_bounds(one);
  EXPECT_FLOAT_EQ(scene_extent(SceneBvh4(one).bvh()), 5.0f);
  const Scene ball = tessellated_sphere(5, {1, 2, 3}, 2.0f);
  float3 lo = ball.positions[0], hi = ball.positions[0];
  for (const float3& p : ball.positions)
    for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
  EXPECT_NEAR(scene_extent(SceneBvh4(ball).bvh()), length(hi - lo), 1e-5f * length(hi - lo));  // boxes round outwards
  EXPECT_EQ(scene_extent(SceneBvh4(Scene{}).bvh()), 0.0f);
}

// The walks the stream leaves to single rays, run eight in flight: from
// every child of the root, under a nearest hit already found, each walk ends
// where the single-ray traversal from the same node ends.
// `prefetching`: whether the tree is one whose walks prefetch (walks_prefetch).
void expect_interleaved_walks_match_single_rays(const Scene& sphere, size_t ray_count, bool prefetching) {
  SceneBvh4 scene_bvh(sphere);
  const Bvh4& bvh = scene_bvh.bvh();
  ASSERT_FALSE(bvh4_ref::is_leaf(bvh.root));
  ASSERT_EQ(walks_prefetch(bvh), prefetching);
  std::vector<Ray> rays = uniform_random_rays(sphere, ray_count, 20);
  struct Walk {
    uint32_t ray, start;
    Hit hit;
  };
  std::vector<Walk> walks;
  for (uint32_t i = 0; i < rays.size(); ++i)
    for (uint32_t c : bvh.node(bvh.root).child) {
      if (c == bvh4_ref::kEmptyRef) continue;
      Hit first;  // a nearest hit found elsewhere: the ray's own, pushed out a little, or none
      scene_bvh.intersect(rays[i], first);
      walks.push_back(
          {i, c, first.valid() && i % 2 ? Hit{first.t * 1.01f, 0, 0, 7} : Hit{rays[i].tmax, 0, 0, kInvalidId}});
    }
  NoCounters counters;
  size_t next = 0, found = 0;
  auto next_walk = [&](Ray& r, uint32_t& from, Hit& h, uint32_t& tag) {
    if (next == walks.size()) return false;
    r = rays[walks[next].ray], from = walks[next].start, h = walks[next].hit, tag = uint32_t(next);
    ++next;
    return true;
  };
  auto never = [](uint32_t) { return false; };
  std::vector<std::pair<Hit, bool>> got(walks.size());
  walk_interleaved<false, 8>(
      bvh, next_walk,
      [&](uint32_t tag, const Hit& h, bool f) {
        got[tag] = {h, f};
      },
      never, counters);
  for (size_t w = 0; w < walks.size(); ++w) {
    Hit alone = walks[w].hit;
    const bool f = walk_ray<false>(bvh, walks[w].start, rays[walks[w].ray], alone, counters);
    EXPECT_EQ(got[w].second, f) << "walk " << w;
    EXPECT_TRUE(same_bits(got[w].first, alone)) << "walk " << w;
    found += f;
  }
  EXPECT_GT(found, walks.size() / 8);  // many walks find a nearer hit
  next = 0;
  std::vector<int> blocked(walks.size(), -1);
  walk_interleaved<true, 8>(
      bvh, next_walk, [&](uint32_t tag, const Hit&, bool b) { blocked[tag] = b; }, never, counters);
  for (size_t w = 0; w < walks.size(); ++w) {
    Hit end = walks[w].hit;
    EXPECT_EQ(blocked[w], int(walk_ray<true>(bvh, walks[w].start, rays[walks[w].ray], end, counters))) << "walk " << w;
  }
  // Walks already answered (every third) end unanswered; the others as before.
  next = 0;
  std::vector<int> again(walks.size(), -1);
  walk_interleaved<true, 8>(
      bvh, next_walk, [&](uint32_t tag, const Hit&, bool b) { again[tag] = b; },
      [](uint32_t tag) { return tag % 3 == 0; }, counters);
  for (size_t w = 0; w < walks.size(); ++w) EXPECT_EQ(again[w], w % 3 == 0 ? -1 : blocked[w]) << "walk " << w;
}

TEST(Bvh4Queue, InterleavedWalksBelowANodeMatchSingleRayWalks) {
  // 5,120 triangles, a tree the L2 cache holds (240 KB, under l2_cache_bytes()): no prefetches.
  expect_interleaved_walks_match_single_rays(tessellated_sphere(4, {0, 0, 0}, 1.0f), 500, false);
}

TEST(Bvh4Queue, InterleavedWalksThatPrefetchMatchSingleRayWalks) {
  // 327,680 triangles: a tree past l2_cache_bytes() (15 MB), whose walks load the
  // next node or leaf ahead.
  expect_interleaved_walks_match_single_rays(tessellated_sphere(7, {0, 0, 0}, 1.0f), 200, true);
}

TEST(Bvh4Queue, ADeepTreeWhoseListsThinOutMatchesSingleRays) {
  // 81,920 triangles in a sphere: rays from inside part ways after a few
  // levels, so that lists fall below the stream's minimum and go on alone.
  Scene sphere = tessellated_sphere(6, {0, 0, 0}, 1.0f);
  SceneBvh4 bvh(sphere);
  QueueScratch scratch;
  std::vector<Ray> rays = uniform_random_rays(sphere, 9000, 17);
  for (Ray& r : rays) r.org = r.org * 0.5f;  // inside
  size_t ties = expect_queue_matches_single_rays(bvh, rays, scratch, "inside a fine sphere");
  EXPECT_LE(ties, 2u);
  Queue q(rays);
  bvh.intersect_queue(q.rays(), q.hits(), scratch);
  int hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) hits += q.hit(i).valid();
  EXPECT_EQ(hits, int(rays.size()));  // a closed mesh: every ray from inside hits it
}

TEST(Bvh4Queue, EveryQueueLengthAroundTheLaneWidthAndThePartSize) {
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  std::vector<Ray> rays = uniform_random_rays(s, 9000, 8);
  std::vector<size_t> lengths = {0, 1, 2, 100, 4095, 4096, 4097, 8193, 9000};
  for (size_t n = lanes() - 1; n <= 2 * lanes() + 1; ++n) lengths.push_back(n);
  for (size_t n : lengths)
    expect_queue_matches_single_rays(bvh, std::span<const Ray>(rays).first(n), scratch,
                                     "queue of " + std::to_string(n));
}

/// Bundles of `n` rays (n from 1 to 64, then again) towards a fine sphere of
/// radius 1 at the origin: each bundle from one point at distance 2.5 (within
/// 0.01) towards a spot of radius 0.03 on a disc of radius 1.3 across the
/// sphere, so that some bundles hit it, some pass by, some graze its edge, and
/// the rays of a bundle reach the same leaves. Every third ray that hits
/// starts just past its entry point and ends 0.05 beyond it (blocked with
/// tmin = 0, unblocked with its tmin).
std::vector<Ray> bundles_at_a_sphere(const SceneBvh4& bvh, size_t total, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  auto unit = [&] {
    for (;;) {
      float3 v{u(rng), u(rng), u(rng)};
      if (float l = length(v); l > 0.1f && l <= 1.0f) return v * (1.0f / l);
    }
  };
  auto across = [&](const float3& axis) {  // a unit vector at right angles to axis
    for (;;) {
      float3 v = unit();
      v = v - axis * dot(v, axis);
      if (float l = length(v); l > 0.1f) return v * (1.0f / l);
    }
  };
  std::vector<Ray> rays;
  for (size_t n = 1; rays.size() < total; n = n % 64 + 1) {
    const float3 axis = unit(), from = axis * 2.5f;
    const float3 spot = across(axis) * (1.3f * std::abs(u(rng)));
    for (size_t i = 0; i < n && rays.size() < total; ++i) {
      const float3 to = spot + unit() * 0.03f, org = from + unit() * 0.01f;
      Ray r{org, 0.0f, to - org, 2.0f};
      Hit h;
      if (rays.size() % 3 == 0 && bvh.intersect(r, h)) r.tmin = h.t * 1.001f, r.tmax = h.t + 0.05f;
      rays.push_back(r);
    }
  }
  return rays;
}

TEST(Bvh4Queue, QueuesOfAtMost64RaysGoAsOneMaskedSetAndMatchSingleRays) {
  // Parts of at most 64 rays are traced for any hit as one set with a mask
  // per node (occluded_masked_part): every length from 1 to 65 in a deep
  // tree, with mixed answers and tmin past an occluder; a short last part
  // after a full one; counted queries; a scene with spheres, which block
  // rays before the tree.
  Scene sphere = tessellated_sphere(5, {0, 0, 0}, 1.0f);
  SceneBvh4 fine(sphere);
  QueueScratch scratch;
  std::vector<Ray> rays = bundles_at_a_sphere(fine, 4096 + 64, 31);
  size_t blocked = 0, by_tmin = 0;
  for (const Ray& r : rays) {
    blocked += fine.occluded(r);
    Ray from_zero = r;
    from_zero.tmin = 0.0f;
    by_tmin += r.tmin > 0.0f && fine.occluded(from_zero) && !fine.occluded(r);
  }
  EXPECT_GT(blocked, rays.size() / 5);  // both answers are exercised
  EXPECT_LT(blocked, rays.size() - rays.size() / 5);
  EXPECT_GT(by_tmin, rays.size() / 20);  // tmin decides for these
  // First, so that the scratch past each shorter queue holds live values.
  expect_queue_matches_single_rays(fine, std::span<const Ray>(rays).first(4096 + 30), scratch,
                                   "a full part, then 30 rays");
  for (size_t n = 1, start = 0; n <= 65; ++n) {
    // Each queue ends with a blocked ray, so that a lane past its end that
    // was traced as a copy of the last ray would write past the queue.
    start = (start + 37) % 4000;
    while (!fine.occluded(rays[start + n - 1])) ++start;
    expect_queue_matches_single_rays(fine, std::span<const Ray>(rays).subspan(start, n), scratch,
                                     "queue of " + std::to_string(n));
  }
  for (size_t n : {9u, 40u, 64u}) {  // counted: the same answers
    Queue q(std::span<const Ray>(rays).subspan(2000, n));
    TraversalCounters c;
    fine.occluded_queue(q.rays(), q.blocked.data(), scratch, &c);
    for (size_t i = 0; i < n; ++i)
      EXPECT_EQ(q.blocked[i], uint8_t(fine.occluded(rays[2000 + i]))) << n << " counted, ray " << i;
    EXPECT_GT(c.nodes, 0u);
  }
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  std::vector<Ray> camera = camera_rays(s, 64, 48);
  std::vector<Hit> first(camera.size());
  for (size_t i = 0; i < camera.size(); ++i) bvh.intersect(camera[i], first[i]);
  std::vector<Ray> shadow = shadow_rays(s, camera, first, 4);
  for (size_t n : {1u, 17u, 33u, 64u})
    expect_queue_matches_single_rays(bvh, std::span<const Ray>(shadow).first(n), scratch,
                                     "Cornell box shadow queue of " + std::to_string(n));
}

TEST(Bvh4Queue, LongQueuesWithTminInEveryPartMatchSingleRays) {
  // Three parts of the stream; tmin > 0 on rays of the later parts too, so
  // that each part's offset into tmin counts.
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  std::vector<Ray> rays = uniform_random_rays(s, 9001, 18);
  start_past_origin(rays, 3, 19);
  expect_queue_matches_single_rays(bvh, rays, scratch, "9001 rays with tmin > 0");
}

TEST(Bvh4Queue, CameraSetsWithATailTminAndUntraceableLanesMatchSingleRays) {
  // A camera queue (traced as sets) whose length is no multiple of K, with
  // a near clip (tmin > 0), untraceable rays among the coherent runs, and
  // rays aimed exactly at the mesh's vertices (edges and corners meet there).
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  std::vector<Ray> pixels = camera_rays(s, 16, 12), rays;
  for (const Ray& p : pixels)
    for (int k = 0; k < 16; ++k) rays.push_back({p.org, 0.05f, p.dir + float3{1e-4f * k, 0.0f, 0.0f}, p.tmax});
  const float3 eye = pixels[0].org;
  for (size_t v = 0; v < s.positions.size() && rays.size() < 64 * 16 + 16 * 7; ++v)
    for (int k = 0; k < 4; ++k) rays.push_back({eye, 0.05f, s.positions[v] - eye, kInfinity});
  rays.resize(rays.size() - 5);   // a partial last set
  rays[16 * 3 + 2].dir.x = NAN;   // inside a coherent run
  rays[16 * 5 + 7].tmax = 0.01f;  // empty range: below the near clip
  expect_queue_matches_single_rays(bvh, rays, scratch, "camera sets");
}

TEST(Bvh4Queue, RaysThatStartPastTheirOriginMatchSingleRays) {
  // tmin > 0 on some rays: the lists carry tmin, which the node and triangle
  // tests must honour (a ray must not find what lies before its tmin).
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  std::vector<Ray> rays = uniform_random_rays(s, 3000, 12);
  start_past_origin(rays, 2, 4);
  expect_queue_matches_single_rays(bvh, rays, scratch, "tmin > 0");
  int skipped = 0;  // some rays really do skip a nearer surface
  for (size_t i = 0; i < rays.size(); i += 2) {
    Ray from_zero = rays[i];
    from_zero.tmin = 0.0f;
    Hit a, b;
    bvh.intersect(rays[i], a);
    bvh.intersect(from_zero, b);
    skipped += a.valid() && b.valid() && a.t > b.t;
  }
  EXPECT_GT(skipped, 100);
}

TEST(Bvh4Queue, NullTminMeansZero) {
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  std::vector<Ray> rays = uniform_random_rays(s, 500, 13);
  Queue with(rays), without(rays);
  bvh.intersect_queue(with.rays(true), with.hits(), scratch);
  bvh.intersect_queue(without.rays(false), without.hits(), scratch);
  bvh.occluded_queue(with.rays(true), with.blocked.data(), scratch);
  bvh.occluded_queue(without.rays(false), without.blocked.data(), scratch);
  for (size_t i = 0; i < rays.size(); ++i) {
    EXPECT_TRUE(same_bits(with.hit(i), without.hit(i))) << "ray " << i;
    EXPECT_EQ(with.blocked[i], without.blocked[i]) << "ray " << i;
  }
}

TEST(Bvh4Queue, UntraceableRaysMissAndSpareTheOthers) {
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  std::vector<Ray> rays = uniform_random_rays(s, 64, 3);
  rays[1].org.x = NAN;
  rays[2].dir.y = INFINITY;
  rays[3].tmin = NAN;
  rays[4].tmax = -1.0f;  // empty range
  rays[5].dir = float3{0.0f};
  rays[6].tmax = NAN;
  expect_queue_matches_single_rays(bvh, rays, scratch, "untraceable rays");
  Queue q(rays);
  bvh.intersect_queue(q.rays(), q.hits(), scratch);
  bvh.occluded_queue(q.rays(), q.blocked.data(), scratch);
  for (size_t i = 1; i <= 6; ++i) {
    EXPECT_FALSE(q.hit(i).valid()) << "ray " << i;
    EXPECT_EQ(q.blocked[i], 0) << "ray " << i;
  }
}

TEST(Bvh4Queue, OcclusionAnswersDoNotDependOnWhatTheOutputHeld) {
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  QueueScratch scratch;
  std::vector<Ray> rays = uniform_random_rays(s, 2000, 14);
  Queue zeros(rays), ones(rays);
  std::fill(zeros.blocked.begin(), zeros.blocked.end() - 1, 0);
  std::fill(ones.blocked.begin(), ones.blocked.end() - 1, 1);
  bvh.occluded_queue(zeros.rays(), zeros.blocked.data(), scratch);
  bvh.occluded_queue(ones.rays(), ones.blocked.data(), scratch);
  EXPECT_EQ(zeros.blocked, ones.blocked);
}

/// Sky-like shadow rays around and through a closed mesh centred at the
/// origin: from anywhere in its box (inside and outside), in uniformly random
/// directions, with the edge cases of the slab constants mixed in: every 5th ray short (from inside, some get out of
/// nothing), every 7th starting past its origin, every 11th with a +0 or -0 component (the octant of -0 is the negative
/// one, as a single ray's), every 13th with a component under NodeRay::kMinDir of either sign (clamped).
std::vector<Ray> sky_like_rays(const Scene& mesh, size_t n, uint32_t seed) {
  std::vector<Ray> rays = uniform_random_rays(mesh, n, seed);
  start_past_origin(rays, 7, seed + 1);
  for (size_t i = 0; i < rays.size(); ++i) {
    if (i % 5 == 1) rays[i].tmax = 0.3f;
    if (i % 11 == 3) rays[i].dir.x = i % 2 ? -0.0f : 0.0f;
    if (i % 13 == 4) rays[i].dir.z = i % 2 ? -1e-20f : 1e-20f;
  }
  return rays;
}

TEST(Bvh4Queue, OnlyShortQueuesOverTheWholeSphereInATreePastL2GoAsOctantSets) {
  // goes_as_octant_sets: a sky's samples (directions over the whole sphere)
  // in queues of at most an eighth of a stream's part, in a tree that one
  // core's L2 does not hold, at 4 or 8 lanes; not an area light's cone of
  // directions, a directional light's one direction, a longer queue, a tree
  // that the L2 holds or 16 lanes.
  const Scene fine_mesh = tessellated_sphere(6, {0, 0, 0}, 1.0f), coarse_mesh = tessellated_sphere(4, {0, 0, 0}, 1.0f);
  SceneBvh4 fine(fine_mesh), coarse(coarse_mesh);
  const size_t l2 = size_t(1) << 20;  // an L2 of 1 MiB, between the two trees (0.24 and 3.8 MB)
  const size_t part = kPartRays, most = part / 8;
  ASSERT_GT(fine.bvh().bytes(), l2);
  ASSERT_LT(coarse.bvh().bytes(), l2);
  auto goes = [&](const SceneBvh4& bvh, std::span<const Ray> q, size_t lanes) {
    return goes_as_octant_sets(Queue(q).rays(), lanes, bvh.bvh().bytes(), l2, part);
  };
  const std::vector<Ray> sky = uniform_random_rays(fine_mesh, most + 1, 40);
  const std::span<const Ray> all(sky);
  for (size_t n : {size_t(16), size_t(127), size_t(128), size_t(375), most}) {
    for (size_t lanes : {4u, 8u}) {
      EXPECT_TRUE(goes(fine, all.first(n), lanes)) << n << " rays";
      EXPECT_FALSE(goes(coarse, all.first(n), lanes)) << n << " rays";
    }
    EXPECT_FALSE(goes(fine, all.first(n), 16)) << n << " rays";
  }
  EXPECT_FALSE(goes(fine, all, 8));  // one ray too many
  std::mt19937 rng(41);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  std::vector<Ray> area, directional;
  for (const Ray& r : all.first(most)) {
    const float3 on_light{2.0f * u(rng), 6.0f, 2.0f * u(rng)};  // a 4 x 4 light 5 above the box
    area.push_back({r.org, 0.0f, on_light - r.org, 1.0f});
    directional.push_back({r.org, 0.0f, {0.3f, 1.0f, 0.2f}, kInfinity});
  }
  EXPECT_FALSE(goes(fine, area, 8));
  EXPECT_FALSE(goes(fine, directional, 8));
  EXPECT_EQ(direction_spread(Queue(directional).rays(), 0, directional.size()), 0.0f);
  // The spread, exactly: +x, -x and +y (any length) range 2 on x, 1 on y,
  // 0 on z; a NaN, an infinite and a zero direction count for nothing. A
  // spread of exactly kSphereSpread does not span the sphere.
  std::vector<Ray> three = {{{0, 0, 0}, 0.0f, {3, 0, 0}, 1.0f},         {{0, 0, 0}, 0.0f, {-0.5f, 0, 0}, 1.0f},
                            {{0, 0, 0}, 0.0f, {0, 2, 0}, 1.0f},         {{0, 0, 0}, 0.0f, {NAN, 0, 1}, 1.0f},
                            {{0, 0, 0}, 0.0f, {0, -INFINITY, 0}, 1.0f}, {{0, 0, 0}, 0.0f, {0, 0, 0}, 1.0f}};
  EXPECT_EQ(direction_spread(Queue(three).rays(), 0, three.size()), 3.0f);
  EXPECT_FALSE(spans_the_sphere(Queue(three).rays()));
  three.push_back({{0, 0, 0}, 0.0f, {0, 0, 1e-3f}, 1.0f});
  EXPECT_FLOAT_EQ(direction_spread(Queue(three).rays(), 0, three.size()), 4.0f);
  EXPECT_TRUE(spans_the_sphere(Queue(three).rays()));
  // A sky queue of 512 rays with one quarter's run along one direction: the
  // queue is judged by every quarter.
  std::vector<Ray> one_run_aligned(sky.begin(), sky.begin() + most);
  for (size_t i = 384; i < 384 + kSpreadRun; ++i) one_run_aligned[i].dir = {0, 0, 1};
  EXPECT_FALSE(spans_the_sphere(Queue(one_run_aligned).rays()));
}

TEST(Bvh4Queue, SkyLikeQueuesMatchSingleRaysAndDoTheirWork) {
  // Any-hit queues of a sky's samples (directions over the whole sphere),
  // every length from 1 to 100 and longer ones, from inside and outside a
  // fine sphere, with short rays, tmin > 0, +-0 and clamped components, and
  // untraceable rays: each ray gets its single-ray answer, counted or not.
  // Those that go as octant sets (short ones at up to 8 lanes, in a tree
  // past L2) visit exactly the nodes and triangles each ray visits alone; the
  // others (a stream) count work. A sphere primitive in the scene blocks some
  // rays before the tree.
  Scene mesh = tessellated_sphere(6, {0, 0, 0}, 1.0f);
  SceneBvh4 bvh(mesh);
  QueueScratch scratch;
  std::vector<Ray> rays = sky_like_rays(mesh, 8000, 42);
  for (size_t i = 0; i < rays.size(); i += 97) rays[i].dir.y = NAN;
  for (size_t i = 50; i < rays.size(); i += 101) rays[i].tmax = rays[i].tmin;  // empty range
  size_t blocked = 0;
  for (const Ray& r : rays) blocked += bvh.occluded(r);
  EXPECT_GT(blocked, rays.size() / 5);  // both answers are exercised
  EXPECT_LT(blocked, rays.size() - rays.size() / 5);
  size_t start = 0, as_sets = 0;
  auto check = [&](size_t n, const std::string& what) {
    start = (start + 613) % (rays.size() - n);
    const std::span<const Ray> q = std::span<const Ray>(rays).subspan(start, n);
    expect_queue_matches_single_rays(bvh, q, scratch, what);
    Queue counted(q);
    TraversalCounters queue_work, alone_work;
    bvh.occluded_queue(counted.rays(), counted.blocked.data(), scratch, &queue_work);
    size_t traceable = 0;
    for (size_t i = 0; i < n; ++i) {
      EXPECT_EQ(counted.blocked[i], uint8_t(bvh.occluded(q[i], &alone_work))) << what << " counted, ray " << i;
      traceable += q[i].tmin < q[i].tmax && !std::isnan(q[i].dir.y);
    }
    const bool sets = n >= 16 && goes_as_octant_sets(Queue(q).rays(), lanes(), bvh.bvh().bytes(), l2_cache_bytes(),
                                                     kPartRays);  // past the stream's minimum (2-8 rays)
    as_sets += sets;
    if (sets) {
      EXPECT_EQ(queue_work.nodes, alone_work.nodes) << what;
      EXPECT_EQ(queue_work.primitives, alone_work.primitives) << what;
    } else if (traceable > 0) {
      EXPECT_GT(queue_work.nodes, 0u) << what;
    }
  };
  for (size_t n = 1; n <= 100; ++n) check(n, "sky queue of " + std::to_string(n));
  for (size_t n : {size_t(127), size_t(129), size_t(255), size_t(375), size_t(512), size_t(4097)})
    check(n, "sky queue of " + std::to_string(n));
  for (Ray& r : rays) r.org = r.org * 0.5f;  // all inside
  for (size_t n : {size_t(33), size_t(200), size_t(512)}) check(n, "sky queue from inside of " + std::to_string(n));
  if (bvh.bvh().bytes() > l2_cache_bytes() && lanes() <= 8) {
    EXPECT_EQ(as_sets, 85u + 5u + 3u);  // every queue of 16 to 512 rays
  } else {
    EXPECT_EQ(as_sets, 0u);
  }
  mesh.spheres.push_back({{0.3f, 0.2f, -0.1f}, 0.4f, mesh.triangle_material[0]});
  mesh.bounds = compute_scene_bounds(mesh);
  SceneBvh4 with_sphere(mesh);
  for (size_t n : {size_t(40), size_t(300)}) {
    const std::span<const Ray> q = std::span<const Ray>(rays).first(n);
    expect_queue_matches_single_rays(with_sphere, q, scratch, "with a sphere, " + std::to_string(n) + " rays");
  }
}

TEST(Bvh4Queue, AnEmptySceneHitsNothing) {
  Scene empty;
  SceneBvh4 bvh(empty);
  QueueScratch scratch;
  std::vector<Ray> rays = uniform_random_rays(built_in_scene(), 100, 16);
  Queue q(rays);
  bvh.intersect_queue(q.rays(), q.hits(), scratch);
  bvh.occluded_queue(q.rays(), q.blocked.data(), scratch);
  for (size_t i = 0; i < rays.size(); ++i) {
    EXPECT_TRUE(same_bits(q.hit(i), Hit{rays[i].tmax, 0.0f, 0.0f, kInvalidId})) << "ray " << i;
    EXPECT_EQ(q.blocked[i], 0) << "ray " << i;
  }
}

}  // namespace
}  // namespace pt::test
