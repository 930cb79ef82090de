// Helpers of the BVH4 test suites: the hit-equality rule of the suites, the
// oracle's hits, and a tessellated closed sphere; the ray sets are the
// benchmark's.
#pragma once

#include <array>
#include <random>
#include <span>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/math/ray.h"
#include "kernels/math/ray_arrays.h"
#include "kernels/scene/scene.h"
#include "bench/ray_sets.h"
#include "bvh/scene_bvh2.h"

namespace pt::test {

// The ray sets are the benchmark's (bench/ray_sets.h).
using bench::camera_rays;
using bench::diffuse_rays;
using bench::shadow_rays;
using bench::uniform_random_rays;

/// Closest hits of `rays` by the oracle (misses: kInvalidId).
std::vector<Hit> closest_hits(const SceneBvh2& oracle, const std::vector<Ray>& rays);

/// The suites' equality of closest hits (for unit-length directions): both
/// misses; or the same primitive, with t within 1e-5 of max(t, scale) and u, v
/// within 1e-4 (the two tests round differently; `scale` is the scene's largest
/// coordinate magnitude, which bounds their absolute error); or two primitives
/// at the same t within 1e-6 relative (an exact tie, e.g. a shared edge).
::testing::AssertionResult same_closest_hit(const Hit& expected, const Hit& actual, float scale);

/// What a query leaves untouched shows as these: a hit no tracer writes and
/// an occlusion answer that is neither 0 nor 1.
inline constexpr Hit kSentinelHit{-7.0f, -7.0f, -7.0f, 0xDEADBEEFu};
inline constexpr uint8_t kUnwritten = 7;

/// A queue of rays as arrays (RayArrays) with its outputs, hits and
/// occlusion answers, and one entry of slack past the end of every array so
/// that writes past the queue show (they keep kSentinelHit, kUnwritten).
struct QueueArrays {
  std::array<std::vector<float>, 8> field;  // ox, oy, oz, tmin, dx, dy, dz, tmax
  std::vector<float> t, u, v;
  std::vector<uint32_t> prim;
  std::vector<uint8_t> blocked;
  size_t n = 0;

  explicit QueueArrays(std::span<const Ray> rays);
  RayArrays rays(bool with_tmin = true) const {
    return {{field[0].data(), field[1].data(), field[2].data()},
            {field[4].data(), field[5].data(), field[6].data()},
            with_tmin ? field[3].data() : nullptr,
            field[7].data(),
            n};
  }
  HitArrays hits() { return {t.data(), u.data(), v.data(), prim.data()}; }
  Hit hit(size_t i) const { return {t[i], u[i], v[i], prim[i]}; }
};

/// Largest coordinate magnitude of the scene's bounds.
float scene_scale(const Scene& s);

/// A closed sphere mesh: an icosahedron subdivided `levels` times (20 * 4^levels
/// triangles, vertices shared by index) and projected to radius r around c.
Scene tessellated_sphere(int levels, float3 c, float r);

}  // namespace pt::test
