// Helpers of the BVH4 test suites: ray sets for a scene (camera, uniformly
// random, diffuse bounces and shadow rays from first hits), the hit-equality
// rule of the suites, and a tessellated closed sphere.
#pragma once

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/ray.h"
#include "kernels/scene.h"
#include "bvh/scene_bvh2.h"

namespace pt::test {

/// Camera rays through the pixel centres of a w x h image of the scene's
/// camera; with window < 1 only of that central fraction of the film.
std::vector<Ray> camera_rays(const Scene& scene, int w, int h, float window = 1.0f);

/// Origins uniform in the scene bounds (enlarged by 10%), directions uniform
/// on the sphere, t in [0, inf).
std::vector<Ray> uniform_random_rays(const Scene& scene, size_t n, uint32_t seed);

/// Rays that leave the first hits of `rays` (closest hits by `oracle`):
/// cosine-distributed around the geometric normal facing the arriving ray,
/// from the offset origin the renderers use.
std::vector<Ray> diffuse_bounce_rays(const Scene& scene, const SceneBvh2& oracle,
                                     const std::vector<Ray>& rays, uint32_t seed);

/// Rays from the first hits of `rays` towards a uniform point on a random
/// area light (or, without area lights, a random point in the scene bounds),
/// with tmax just short of the target: the renderers' shadow rays.
std::vector<Ray> shadow_rays(const Scene& scene, const SceneBvh2& oracle,
                             const std::vector<Ray>& rays, uint32_t seed);

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
