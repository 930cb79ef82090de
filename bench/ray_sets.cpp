// Ray set generation.
#include "ray_sets.h"

#include <algorithm>
#include <random>

#include "io/camera_setup.h"
#include "kernels/frame.h"
#include "kernels/sampling.h"
#include "kernels/shading.h"
#include "kernels/surface.h"

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

template <class Rng> float uniform01(Rng& rng) { return std::uniform_real_distribution<float>(0.0f, 1.0f)(rng); }

}  // namespace

const char* ray_kind_name(RayKind k) {
  switch (k) {
    case RayKind::kPrimary: return "primary";
    case RayKind::kDiffuse: return "diffuse";
    case RayKind::kShadow: return "shadow";
  }
  return "?";
}

RaySet primary_rays(const Scene& scene, int w, int h) {
  Camera cam = resolve_camera(scene, w, h);
  std::vector<std::pair<uint32_t, Ray>> keyed;
  keyed.reserve(size_t(w) * h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x)
      keyed.push_back({morton2(x, y), camera_ray(cam, (x + 0.5f) / w, 1.0f - (y + 0.5f) / h)});
  std::sort(keyed.begin(), keyed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  RaySet set{RayKind::kPrimary, {}};
  for (const auto& k : keyed) set.rays.push_back(k.second);
  return set;
}

RaySet diffuse_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits, uint32_t seed) {
  std::mt19937 rng(seed);
  RaySet set{RayKind::kDiffuse, {}};
  for (size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i].valid()) continue;
    SurfacePoint sp = surface_at(scene, primary.rays[i], hits[i]);
    float u1 = uniform01(rng), u2 = uniform01(rng);
    float3 dir = to_world(sp.ng, to_float3(sample_cosine_hemisphere(u1, u2)));
    set.rays.push_back({offset_origin(sp, dir), 0.0f, dir, kInfinity});
  }
  std::shuffle(set.rays.begin(), set.rays.end(), rng);
  return set;
}

RaySet shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits, uint32_t seed) {
  std::mt19937 rng(seed);
  RaySet set{RayKind::kShadow, {}};
  for (size_t i = 0; i < hits.size(); ++i) {
    if (!hits[i].valid()) continue;
    SurfacePoint sp = surface_at(scene, primary.rays[i], hits[i]);
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
    set.rays.push_back({offset_origin(sp, dir), 0.0f, dir, tmax});
  }
  std::shuffle(set.rays.begin(), set.rays.end(), rng);
  return set;
}

}  // namespace pt::bench
