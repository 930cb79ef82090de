// Helpers of the BVH4 test suites: the hit-equality rule of the suites, the
// oracle's hits, and a tessellated closed sphere; the ray sets are the
// benchmark's.
#pragma once

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/math/ray.h"
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

/// Largest coordinate magnitude of the scene's bounds.
float scene_scale(const Scene& s);

/// A closed sphere mesh: an icosahedron subdivided `levels` times (20 * 4^levels
/// triangles, vertices shared by index) and projected to radius r around c.
Scene tessellated_sphere(int levels, float3 c, float r);

}  // namespace pt::test
