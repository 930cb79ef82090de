// Fixed ray sets for validating and timing tracers, shared by the benchmark
// and the BVH test suites: camera rays (row by row, or in Morton order, where
// any aligned run of 4, 8 or 16 rays is a 2x2, 4x2 or 4x4 pixel block),
// uniformly random rays, and from the first hits of a set the renderers'
// diffuse-bounce rays and shadow rays. Deterministic for a given scene, size
// and seed.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/math/ray.h"
#include "kernels/scene/scene.h"

namespace pt::bench {

/// Camera rays through the pixel centres of a w x h image of the scene's
/// camera, row by row; with window < 1 only of that central fraction of the film.
std::vector<Ray> camera_rays(const Scene& scene, int w, int h, float window = 1.0f);

/// Origins uniform in the scene bounds (enlarged by 10%), directions uniform
/// on the sphere, t in [0, inf).
std::vector<Ray> uniform_random_rays(const Scene& scene, size_t n, uint32_t seed);

/// From every hit (hits[i] of rays[i]; misses are skipped): a cosine-distributed
/// direction around the geometric normal facing the arriving ray, from the
/// renderers' offset origin. Shuffled with the same generator when `shuffle`.
std::vector<Ray> diffuse_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits, uint32_t seed,
                              bool shuffle = false);

/// From every hit: towards a uniform point on a random area light (tmax just
/// short of it), or without area lights, along a uniform direction of the
/// upper hemisphere (tmax = inf). Shuffled with the same generator when `shuffle`.
std::vector<Ray> shadow_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits, uint32_t seed,
                             bool shuffle = false);

enum class RayKind { kPrimary, kDiffuse, kShadow };
const char* ray_kind_name(RayKind k);

/// The benchmark's sets: primary camera rays in Morton order, then shuffled
/// diffuse and shadow rays from their first hits.
struct RaySet {
  RayKind kind;
  std::vector<Ray> rays;
  bool occlusion() const { return kind == RayKind::kShadow; }
};

/// Camera rays of a w x h image (w, h multiples of 4) in Morton order over (x, y).
RaySet primary_rays(const Scene& scene, int w, int h);

}  // namespace pt::bench
