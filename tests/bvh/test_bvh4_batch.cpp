// The batched entry points of SceneBvh4 at the instruction-set level in use:
// every batch length 1..3K+1 (K = its packet width) answers like the
// single-ray query; entries past the batch and lanes left out
// of a packet are untouched (and their rays unread); rays that are not
// traceable or that disagree on direction signs inside a packet; spheres; the
// watertight form; range queries and the benchmark's incoherent batches,
// reordered or not.
#include <algorithm>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "bench/incoherent_batch.h"
#include "bvh/scene_bvh4.h"
#include "support/bvh4_support.h"
#include "support/test_support.h"

namespace pt::test {
namespace {

const Hit kSentinel{-7.0f, -7.0f, -7.0f, 0xDEADBEEFu};

/// K: the packet width of the level in use.
size_t packet_lanes() { return isa_lanes(active_isa()); }

bool is_sentinel(const Hit& h) { return std::memcmp(&h, &kSentinel, sizeof(Hit)) == 0; }

Scene built_in_scene() { return load_collada_file(project_scene("cornell_spheres.dae")).scene; }

/// Camera rays through the middle of the view, then uniformly random rays
/// (mixed direction signs).
std::vector<Ray> test_rays(const Scene& s) {
  std::vector<Ray> rays = camera_rays(s, 24, 16, 0.3f);
  std::vector<Ray> random = uniform_random_rays(s, 200, 21);
  rays.insert(rays.end(), random.begin(), random.end());
  return rays;
}

void expect_batches_match_single_rays(const Scene& s, const Bvh4Options& options) {
  SceneBvh4 bvh(s, options);
  std::vector<Ray> rays = test_rays(s);
  float scale = scene_scale(s);
  int hits_in_first_batches = 0;
  for (size_t i = 0; i < 3 * packet_lanes() + 1; ++i) {
    Hit h;
    hits_in_first_batches += bvh.intersect(rays[i], h);
  }
  EXPECT_GT(hits_in_first_batches, int(packet_lanes()));  // the comparisons below are not all misses
  for (size_t n = 1; n <= 3 * packet_lanes() + 1; ++n)
    for (size_t first : {size_t{0}, size_t{384}}) {  // coherent camera rays, then random rays
      std::vector<Hit> hits(n + 8, kSentinel);
      bvh.intersect(std::span<const Ray>(rays.data() + first, n), std::span<Hit>(hits.data(), n));
      for (size_t i = 0; i < n; ++i) {
        Hit single;
        bvh.intersect(rays[first + i], single);
        EXPECT_TRUE(same_closest_hit(single, hits[i], scale)) << "batch of " << n << ", ray " << first + i;
      }
      for (size_t i = n; i < hits.size(); ++i) EXPECT_TRUE(is_sentinel(hits[i])) << "batch of " << n << " wrote " << i;
    }
}

TEST(Bvh4Batch, EveryLengthMatchesSingleRays) {
  expect_batches_match_single_rays(built_in_scene(), {});
  expect_batches_match_single_rays(tessellated_sphere(4, {0, 0, 0}, 1.0f), {});
}

TEST(Bvh4Batch, WatertightFormMatchesSingleRays) {
  Bvh4Options watertight;
  watertight.watertight = true;
  expect_batches_match_single_rays(built_in_scene(), watertight);
}

TEST(Bvh4Batch, LanesLeftOutAreNeitherReadNorWritten) {
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  std::vector<Ray> good = camera_rays(s, 8, int(packet_lanes()), 0.3f);
  std::mt19937 rng(5);
  for (int trial = 0; trial < 200; ++trial) {
    uint32_t lanes = static_cast<uint32_t>(rng()) & lanes_below(packet_lanes());
    std::vector<Ray> rays(packet_lanes());
    std::vector<Hit> hits(packet_lanes(), kSentinel);
    for (size_t i = 0; i < packet_lanes(); ++i) {
      rays[i] = good[(trial * 7 + i * 13) % good.size()];
      if (!(lanes >> i & 1)) rays[i] = Ray{float3(NAN), NAN, float3(NAN), NAN};  // garbage if read
    }
    bvh.intersect_packet(rays.data(), hits.data(), lanes);
    for (size_t i = 0; i < packet_lanes(); ++i) {
      if (!(lanes >> i & 1)) {
        EXPECT_TRUE(is_sentinel(hits[i])) << "lane " << i << " written";
        continue;
      }
      Hit single;
      bvh.intersect(rays[i], single);
      EXPECT_TRUE(same_closest_hit(single, hits[i], scene_scale(s))) << "lane " << i;
    }
  }
}

TEST(Bvh4Batch, UntraceableRaysInAPacketMissAndSpareTheOthers) {
  Scene s = built_in_scene();
  SceneBvh4 bvh(s);
  const size_t n = std::max<size_t>(packet_lanes(), 16);  // one packet on AVX-512, four with SSE
  std::vector<Ray> rays = uniform_random_rays(s, n, 3);   // from inside the room
  rays[1].org.x = NAN;
  rays[2].dir.y = INFINITY;
  rays[3].tmin = NAN;
  rays[4].tmax = -1.0f;  // empty range
  rays[5].dir = float3{0.0f};
  std::vector<Hit> hits(n, kSentinel);
  bvh.intersect(rays, hits);
  for (size_t i = 1; i <= 5; ++i) EXPECT_FALSE(hits[i].valid()) << "ray " << i;
  int traceable_hits = 0;
  for (size_t i = 0; i < n; ++i) {
    Hit single;
    bvh.intersect(rays[i], single);
    EXPECT_TRUE(same_closest_hit(single, hits[i], scene_scale(s))) << "ray " << i;
    traceable_hits += i > 5 && hits[i].valid();
  }
  EXPECT_GT(traceable_hits, 0);  // the others still find the room
}

TEST(Bvh4Batch, SpheresAreFoundByPackets) {
  Scene s = built_in_scene();
  ASSERT_FALSE(s.spheres.empty());
  SceneBvh4 bvh(s);
  std::vector<Ray> rays;
  for (const Sphere& sphere : s.spheres)
    for (size_t i = 0; i < packet_lanes(); ++i) {  // rays from the camera side straight at the sphere
      float3 target =
          sphere.center + float3{0.1f * float(i % 4) - 0.15f, 0.1f * float(i / 4) - 0.15f, 0.0f} * sphere.radius;
      float3 from = sphere.center + float3{0.0f, 0.0f, 4.0f * sphere.radius};
      rays.push_back({from, 0.0f, normalize(target - from), kInfinity});
    }
  std::vector<Hit> hits(rays.size(), kSentinel);
  bvh.intersect(rays, hits);
  int sphere_hits = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit single;
    bvh.intersect(rays[i], single);
    EXPECT_TRUE(same_closest_hit(single, hits[i], scene_scale(s))) << "ray " << i;
    sphere_hits += hits[i].is_sphere();
  }
  EXPECT_GT(sphere_hits, 0);
}

/// The benchmark's incoherent batches of rays[0, n), in input order and
/// reordered, and the range queries, against single rays.
void expect_incoherent_batches_match(const Scene& s, const std::vector<Ray>& rays, std::vector<size_t> lengths) {
  SceneBvh4 bvh(s);
  for (size_t reorder_min_bytes : {size_t(0), SIZE_MAX}) {
    bench::IncoherentBatches batches(bvh, s, reorder_min_bytes);
    for (size_t n : lengths) {
      std::vector<Hit> hits(n + 4, kSentinel), each(n + 4, kSentinel);
      std::vector<uint8_t> blocked(n + 4, 7), blocked_each(n + 4, 7);
      batches.intersect(std::span<const Ray>(rays.data(), n), std::span<Hit>(hits.data(), n));
      batches.occluded(std::span<const Ray>(rays.data(), n), std::span<uint8_t>(blocked.data(), n));
      bvh.intersect_each(std::span<const Ray>(rays.data(), n), std::span<Hit>(each.data(), n));
      bvh.occluded_each(std::span<const Ray>(rays.data(), n), std::span<uint8_t>(blocked_each.data(), n));
      EXPECT_EQ(std::memcmp(hits.data(), each.data(), hits.size() * sizeof(Hit)), 0) << "batch of " << n;
      EXPECT_EQ(blocked, blocked_each) << "batch of " << n;
      int found = 0;
      for (size_t i = 0; i < n; ++i) {
        Hit single;
        found += bvh.intersect(rays[i], single);
        EXPECT_TRUE(same_closest_hit(single, hits[i], scene_scale(s))) << "batch of " << n << ", ray " << i;
        EXPECT_EQ(blocked[i], uint8_t(bvh.occluded(rays[i]))) << "batch of " << n << ", ray " << i;
      }
      for (size_t i = n; i < hits.size(); ++i) {
        EXPECT_TRUE(is_sentinel(hits[i])) << "batch of " << n << " wrote " << i;
        EXPECT_EQ(blocked[i], 7) << "batch of " << n << " wrote " << i;
      }
      if (n >= 100) {
        EXPECT_GE(found, int(n / 4));  // the comparisons are not all misses
      }
    }
  }
}

TEST(Bvh4Batch, IncoherentBatchesMatchSingleRays) {
  Scene sphere = tessellated_sphere(4, {0, 0, 0}, 1.0f);
  std::vector<Ray> rays = uniform_random_rays(sphere, 2000, 9);
  std::vector<size_t> lengths = {0, 2000};
  for (size_t n = 1; n <= 3 * packet_lanes() + 1; ++n) lengths.push_back(n);
  expect_incoherent_batches_match(sphere, rays, lengths);
  Scene room = built_in_scene();
  expect_incoherent_batches_match(room, uniform_random_rays(room, 3000, 8), {3000});
}

TEST(Bvh4Batch, PacketsMatchSingleRaysOnSharedScenes) {
  PT_REQUIRE_SHARED_SCENES();
  for (const char* name : {"CBbunny.dae", "CBspheres_lambertian.dae", "teapot.dae"}) {
    Scene s = load_collada_file(shared_scene(name)).scene;
    SceneBvh4 bvh(s);
    std::vector<Ray> rays = camera_rays(s, 64, 48);
    std::vector<Hit> hits(rays.size());
    bvh.intersect(rays, hits);
    int mismatches = 0;
    for (size_t i = 0; i < rays.size() && mismatches < 5; ++i) {
      Hit single;
      bvh.intersect(rays[i], single);
      auto same = same_closest_hit(single, hits[i], scene_scale(s));
      mismatches += !same;
      EXPECT_TRUE(same) << name << " ray " << i;
    }
  }
}

/// occluded_packet over runs of packet_lanes() rays (the last run partial) answers
/// like occluded() per ray, and reports no lane outside `lanes`.
void expect_occlusion_packets_match(const SceneBvh4& bvh, const std::vector<Ray>& rays, const char* what) {
  int blocked_total = 0;
  for (size_t first = 0; first < rays.size(); first += packet_lanes()) {
    size_t n = std::min(packet_lanes(), rays.size() - first);
    uint32_t all = lanes_below(n);
    for (uint32_t lanes : {all, all & 0x5555u, all & 0xF0F0u}) {
      uint32_t blocked = bvh.occluded_packet(&rays[first], lanes);
      EXPECT_EQ(blocked & ~lanes, 0u) << what << ": lanes outside the packet reported";
      for (size_t i = 0; i < n; ++i) {
        if (!(lanes >> i & 1)) continue;
        bool single = bvh.occluded(rays[first + i]);
        blocked_total += single;
        EXPECT_EQ(single, bool(blocked >> i & 1)) << what << " ray " << first + i << " of lanes " << lanes;
      }
    }
  }
  EXPECT_GT(blocked_total, 0) << what << ": the comparison is not all misses";
}

/// Shadow rays from the first hits of camera rays towards `target`, ending
/// just before it: coherent, like a pixel's shadow rays to an area light.
std::vector<Ray> shadow_rays_towards(const SceneBvh4& bvh, const std::vector<Ray>& camera, float3 target) {
  std::vector<Ray> shadows;
  for (const Ray& r : camera) {
    Hit h;
    if (!bvh.intersect(r, h)) continue;
    float3 p = r.org + r.dir * (h.t * 0.999f);
    shadows.push_back({p, 0.0f, target - p, 0.999f});
  }
  return shadows;
}

TEST(Bvh4Batch, OcclusionPacketsMatchSingleRays) {
  Scene room = built_in_scene();  // spheres too
  SceneBvh4 bvh(room);
  std::vector<Ray> camera = camera_rays(room, 32, 24);
  expect_occlusion_packets_match(bvh, shadow_rays_towards(bvh, camera, {0.0f, 1.9f, 0.0f}), "built-in, to the light");
  expect_occlusion_packets_match(bvh, uniform_random_rays(room, 1000, 5), "built-in, random rays");
  Scene sphere = tessellated_sphere(4, {0, 0, 0}, 1.0f);
  SceneBvh4 sphere_bvh(sphere);
  expect_occlusion_packets_match(sphere_bvh, uniform_random_rays(sphere, 1000, 6), "tessellated sphere");
  if (!shared_scenes_available()) return;
  Scene bunny = load_collada_file(shared_scene("CBbunny.dae")).scene;
  SceneBvh4 bunny_bvh(bunny);
  expect_occlusion_packets_match(bunny_bvh,
                                 shadow_rays_towards(bunny_bvh, camera_rays(bunny, 48, 36), {0.0f, 1.45f, 0.0f}),
                                 "CBbunny, to the light");
}

}  // namespace
}  // namespace pt::test
