// The wavefront shades bounce hits sorted by the cell of their hit points
// (wavefront/hit_point_order.h): at the level in use, the sort is a stable
// permutation that carries every field of a ray and its hit, groups hits by
// cell in Morton order (x in the lowest bit) and puts misses last, also when
// one scratch serves queues of decreasing size (as in a render), and when a
// field holds one value (filled, not gathered; a lone -0 among +0 is not one
// value). Hit points
// are exact in float here (quarters, times 1/2, 1 or 2), so that the test's
// own arithmetic cannot put a point in another cell than the sort does.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <random>
#include <vector>

#include "kernels/simd/isa.h"
#include "support/lane_probes.h"
#include "wavefront/hit_point_order.h"
#include "wavefront/streams.h"

namespace pt {
namespace {

#define PT_EXPECT_FIELD(T, name) EXPECT_EQ(out.name[k], in.name[from]) << #name << " of item " << k;

/// The level's sort of a ray queue and its hits (lane_probes.h).
void sort_by_hit_point(const test::LaneProbes& probes, const BBox& bounds, wf::RayQueue& rays, wf::HitQueue& hits) {
  test::StreamColumns ray_columns = test::columns_of(rays), hit_columns = test::columns_of(hits);
  probes.sort_by_hit_point(bounds, ray_columns, hit_columns);
  test::from_columns(ray_columns, rays);
  test::from_columns(hit_columns, hits);
}

/// The 8 x 8 x 8 cell of point p in [0, 8)^3 (outside: clamped), Morton order.
uint32_t expected_cell(float x, float y, float z) {
  auto axis = [](float v) { return static_cast<uint32_t>(std::clamp(v, 0.0f, 7.0f)); };
  uint32_t c[3] = {axis(x), axis(y), axis(z)}, key = 0;
  for (uint32_t bit = 0; bit < 3; ++bit)
    for (uint32_t a = 0; a < 3; ++a) key |= ((c[a] >> bit) & 1u) << (3 * bit + a);
  return key;
}

TEST(HitPointOrder, IsAStablePermutationByCellInMortonOrderWithMissesLast) {
  const test::LaneProbes& probes = test::lane_probes(active_isa());
  const BBox bounds{{0.0f, 0.0f, 0.0f}, {8.0f, 8.0f, 8.0f}};  // cells of edge 1
  std::mt19937 rng(11);
  auto quarter = [&](int lo, int hi) {
    return static_cast<float>(std::uniform_int_distribution<int>(lo, hi)(rng)) / 4;
  };
  for (size_t n : {size_t(5000), size_t(1000), 3 * probes.lanes + 1, probes.lanes, size_t(2), size_t(1)}) {
    wf::RayQueue rays, in_rays;
    wf::HitQueue hits, in_hits;
    rays.reserve(n);
    hits.reserve(n);
    rays.size = hits.size = n;
    std::vector<uint32_t> key(n);
    for (size_t i = 0; i < n; ++i) {
      const float t = std::array{0.5f, 1.0f, 2.0f}[rng() % 3];
      rays.org_x[i] = quarter(-8, 40), rays.org_y[i] = quarter(-8, 40), rays.org_z[i] = quarter(-8, 40);
      rays.dir_x[i] = quarter(-8, 8), rays.dir_y[i] = quarter(-8, 8), rays.dir_z[i] = quarter(-8, 8);
      // A bounce queue's tmin and tmax hold one value (filled, not gathered);
      // a single -0 among +0 must still be carried.
      rays.tmin[i] = n == 1000 ? 0.0f : n == 5000 ? (i == 17 ? -0.0f : 0.0f) : quarter(0, 4);
      rays.tmax[i] = n == 1000 ? kInfinity : quarter(40, 80);
      rays.path[i] = static_cast<uint32_t>(i);
      rays.beta_r[i] = quarter(0, 8), rays.beta_g[i] = quarter(0, 8), rays.beta_b[i] = quarter(0, 8);
      rays.bsdf_pdf[i] = quarter(-4, 8);
      const bool miss = rng() % 10 == 0;
      hits.t[i] = miss ? kInfinity : t;
      hits.u[i] = quarter(0, 4), hits.v[i] = quarter(0, 4);
      hits.prim[i] = miss ? kInvalidId : static_cast<uint32_t>(rng() % 1000);
      key[i] = miss ? 512u
                    : expected_cell(rays.org_x[i] + t * rays.dir_x[i], rays.org_y[i] + t * rays.dir_y[i],
                                    rays.org_z[i] + t * rays.dir_z[i]);
    }
    in_rays = rays;
    in_hits = hits;
    std::vector<uint32_t> expected(n);
    std::iota(expected.begin(), expected.end(), 0u);
    std::stable_sort(expected.begin(), expected.end(), [&](uint32_t a, uint32_t b) { return key[a] < key[b]; });

    sort_by_hit_point(probes, bounds, rays, hits);  // one scratch for every n, as a thread's wave buffers keep theirs
    ASSERT_EQ(rays.size, n);
    ASSERT_EQ(hits.size, n);
    for (size_t k = 0; k < n; ++k) {
      const uint32_t from = expected[k];
      ASSERT_EQ(rays.path[k], from) << "item " << k << " of " << n;
      EXPECT_EQ(std::signbit(rays.tmin[k]), std::signbit(in_rays.tmin[from])) << "tmin of item " << k;
      {
        const wf::RayQueue &in = in_rays, &out = rays;
        PT_RAY_FIELDS(PT_EXPECT_FIELD)
      }
      {
        const wf::HitQueue &in = in_hits, &out = hits;
        PT_HIT_FIELDS(PT_EXPECT_FIELD)
      }
    }
  }
}

TEST(HitPointOrder, AnEmptyOrFlatSceneKeepsTheQueue) {
  const test::LaneProbes& probes = test::lane_probes(active_isa());
  for (const BBox& bounds : {BBox{}, BBox{{0.0f, 0.0f, 0.0f}, {4.0f, 0.0f, 4.0f}}}) {
    wf::RayQueue rays;
    wf::HitQueue hits;
    const size_t n = 3 * probes.lanes + 2;
    rays.reserve(n);
    hits.reserve(n);
    rays.size = hits.size = n;
    for (size_t i = 0; i < n; ++i) {  // all at y = 0; x and z decreasing, so that any sort by them would move them
      rays.org_x[i] = rays.org_z[i] = static_cast<float>(n - i) / static_cast<float>(n) * 4.0f;
      rays.org_y[i] = rays.dir_x[i] = rays.dir_y[i] = rays.dir_z[i] = 0.0f;
      rays.path[i] = static_cast<uint32_t>(i);
      hits.t[i] = 1.0f;
      hits.prim[i] = 7;
    }
    sort_by_hit_point(probes, bounds, rays, hits);
    ASSERT_EQ(rays.size, n);
    const bool flat = bounds.upper.x > bounds.lower.x;
    for (size_t k = 0; k + 1 < n; ++k) {
      if (!flat) EXPECT_EQ(rays.path[k], k) << "empty bounds: one cell, queue order";
      else  // cells of edge 0.5 along x and z; the flat axis has one cell
        EXPECT_LE(std::min(std::floor(rays.org_x[k] * 2.0f), 7.0f),
                  std::min(std::floor(rays.org_x[k + 1] * 2.0f), 7.0f))
            << "a flat scene still sorts along its other axes";
    }
  }
}

}  // namespace
}  // namespace pt
