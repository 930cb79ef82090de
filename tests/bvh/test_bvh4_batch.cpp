// The benchmark's batched queries at the instruction-set level in use
// (bench/bench_queries.h, bench/incoherent_batch.h): ranges of rays traced
// each on its own, and incoherent batches, reordered or not, answer like the
// single-ray queries, for every length 1..3K+1 and longer ones, and write
// nothing past the batch.
#include <algorithm>
#include <cstring>
#include <random>

#include <gtest/gtest.h>

#include "bench/bench_queries.h"
#include "bench/incoherent_batch.h"
#include "bvh/scene_bvh4.h"
#include "support/bvh4_support.h"
#include "support/test_support.h"

namespace pt::test {
namespace {

const Hit kSentinel = kSentinelHit;

/// K: the lane count of the level in use.
size_t lanes() { return isa_lanes(active_isa()); }

bool is_sentinel(const Hit& h) { return std::memcmp(&h, &kSentinel, sizeof(Hit)) == 0; }

Scene built_in_scene() { return load_collada_file(project_scene("cornell_spheres.dae")).scene; }

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
      bench::bench_queries().intersect_each(bvh, std::span<const Ray>(rays.data(), n), std::span<Hit>(each.data(), n));
      bench::bench_queries().occluded_each(bvh, std::span<const Ray>(rays.data(), n),
                                           std::span<uint8_t>(blocked_each.data(), n));
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
  for (size_t n = 1; n <= 3 * lanes() + 1; ++n) lengths.push_back(n);
  expect_incoherent_batches_match(sphere, rays, lengths);
  Scene room = built_in_scene();
  expect_incoherent_batches_match(room, uniform_random_rays(room, 3000, 8), {3000});
}

}  // namespace
}  // namespace pt::test
