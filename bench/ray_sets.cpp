// Ray set generation.
#include "ray_sets.h"

#include <algorithm>
#include <random>

#include "io/camera_setup.h"
#include "kernels/math/frame.h"
#include "kernels/math/sampling.h"
#include "kernels/transport/shading.h"
#include "kernels/transport/surface.h"

namespace pt::bench {
namespace {

/// Interleaves the bits of x and y (x in the even bits).
uint32_t morton2(uint32_t x, uint32_t y) {
  auto spread = [](uint32_t v) {
    v &= 0xFFFF;
    v = (v | v << 8) & 0x00FF00FF;
    v = (v | v << 4) & 0x0F0F0F0F;
    v = (v | v << 2) & 0x33333333;
    v = (v | v << 1) & 0x55555555;
    return v;
  };
  return spread(x) | spread(y) << 1;
}

template <class Rng>
float uniform01(Rng& rng) {
  return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng);
}

}  // namespace

RaySet ray_set(std::string name, bool occlusion, std::vector<Ray> rays) {
  RaySet set{std::move(name), occlusion, std::move(rays), {}};
  for (size_t end = kQueueRays; end < set.rays.size(); end += kQueueRays) set.queue_ends.push_back(end);
  set.queue_ends.push_back(set.rays.size());
  return set;
}

std::vector<Ray> camera_rays(const Scene& scene, int w, int h, float window) {
  Camera cam = resolve_camera(scene, w, h);
  std::vector<Ray> rays;
  rays.reserve(size_t(w) * h);
  float margin = 0.5f * (1.0f - window);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      rays.push_back(camera_ray(cam, margin + window * (x + 0.5f) / w, 1.0f - margin - window * (y + 0.5f) / h));
  return rays;
}

std::vector<Ray> uniform_random_rays(const Scene& scene, size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  float3 lo = scene.bounds.lower - scene.bounds.extent() * 0.05f, ext = scene.bounds.extent() * 1.1f;
  std::vector<Ray> rays(n);
  for (Ray& r : rays) {
    float x = uniform01(rng), y = uniform01(rng), z = uniform01(rng);
    r.org = lo + float3{x, y, z} * ext;
    float u1 = uniform01(rng), u2 = uniform01(rng);
    r.dir = to_float3(sample_uniform_sphere(u1, u2));
  }
  return rays;
}

std::vector<Ray> diffuse_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits, uint32_t seed,
                              bool shuffle) {
  std::mt19937 rng(seed);
  std::vector<Ray> out;
  for (size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i].valid()) continue;
    SurfacePoint sp = surface_at(scene, rays[i], hits[i]);
    float u1 = uniform01(rng), u2 = uniform01(rng);
    float3 dir = to_world(sp.ng, to_float3(sample_cosine_hemisphere(u1, u2)));
    out.push_back({offset_origin(sp, dir), 0.0f, dir, kInfinity});
  }
  if (shuffle) std::shuffle(out.begin(), out.end(), rng);
  return out;
}

std::vector<Ray> shadow_rays(const Scene& scene, std::span<const Ray> rays, std::span<const Hit> hits, uint32_t seed,
                             bool shuffle) {
  std::mt19937 rng(seed);
  std::vector<Ray> out;
  for (size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i].valid()) continue;
    SurfacePoint sp = surface_at(scene, rays[i], hits[i]);
    float u1 = uniform01(rng), u2 = uniform01(rng);
    float3 dir;
    float tmax = kInfinity;
    if (!scene.area_lights.empty()) {
      const AreaLight& l = scene.area_lights[rng() % scene.area_lights.size()];
      float3 d = l.position + l.dim_x * (u1 - 0.5f) + l.dim_y * (u2 - 0.5f) - sp.p;
      float dist = length(d);
      if (!(dist > 0.0f)) continue;
      dir = d / dist;
      tmax = shadow_ray_tmax(dist);
    } else {
      Vec3T<float> h = sample_uniform_hemisphere(u1, u2);
      dir = float3{h.x, h.z, h.y};
    }
    out.push_back({offset_origin(sp, dir), 0.0f, dir, tmax});
  }
  if (shuffle) std::shuffle(out.begin(), out.end(), rng);
  return out;
}

RaySet primary_rays(const Scene& scene, int w, int h) {
  std::vector<Ray> rows = camera_rays(scene, w, h);
  std::vector<std::pair<uint32_t, size_t>> keyed;
  keyed.reserve(rows.size());
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) keyed.push_back({morton2(x, y), size_t(y) * w + x});
  std::sort(keyed.begin(), keyed.end());
  std::vector<Ray> rays;
  rays.reserve(rows.size());
  for (const auto& k : keyed) rays.push_back(rows[k.second]);
  return ray_set("primary", false, std::move(rays));
}

}  // namespace pt::bench
