// Fixed ray sets for validating and timing tracers, shared by the benchmark
// and the BVH test suites: camera rays (row by row, or in Morton order, where
// any aligned run of 4, 8 or 16 rays is a 2x2, 4x2 or 4x4 pixel block),
// uniformly random rays, and from the first hits of a set the renderers'
// diffuse-bounce rays and shadow rays, in the order of their camera rays or
// shuffled. Deterministic for a given scene, size and seed.
#pragma once

#include <cstdint>
#include <span>
#include <string>
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

/// Rays per queue of the synthetic sets: the queue tracer's largest part (it
/// splits the wavefront's queues, from waves of 8192 paths, into such parts).
inline constexpr size_t kQueueRays = 4096;

/// A benchmark's ray set: its rays, in the order they are traced, and the
/// queues they are traced in (a render's, or kQueueRays rays each): queue q
/// is rays [queue_ends[q - 1], queue_ends[q]).
struct RaySet {
  std::string name;
  bool occlusion = false;  ///< any-hit queries (shadow rays); else closest hit
  std::vector<Ray> rays;
  std::vector<size_t> queue_ends;
};

/// A set traced in queues of kQueueRays.
RaySet ray_set(std::string name, bool occlusion, std::vector<Ray> rays);

/// Camera rays of a w x h image (w, h multiples of 4) in Morton order over (x, y).
RaySet primary_rays(const Scene& scene, int w, int h);

}  // namespace pt::bench
