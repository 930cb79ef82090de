// The benchmark's fixed ray sets per scene: primary camera rays in Morton
// order (coherent: any aligned run of 4, 8 or 16 rays is a 2x2, 4x2 or 4x4
// pixel block), diffuse-bounce rays from the first hits (incoherent,
// shuffled) and shadow rays from the first hits to the area light (occlusion,
// shuffled). Deterministic for a given scene and size.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "kernels/ray.h"
#include "kernels/scene.h"

namespace pt::bench {

enum class RayKind { kPrimary, kDiffuse, kShadow };
const char* ray_kind_name(RayKind k);

struct RaySet {
  RayKind kind;
  std::vector<Ray> rays;
  bool occlusion() const { return kind == RayKind::kShadow; }
};

/// Camera rays through the pixel centres of a w x h image (w, h multiples of
/// 4), in Morton order over (x, y).
RaySet primary_rays(const Scene& scene, int w, int h);

/// From every first hit of `primary` (closest hits `hits`): a cosine-distributed
/// direction around the geometric normal facing the arriving ray, from the
/// renderers' offset origin. Shuffled with `seed`.
RaySet diffuse_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits, uint32_t seed);

/// From every first hit: towards a uniform point on a random area light
/// (tmax just short of it), or without area lights, along a uniform direction
/// of the upper hemisphere (tmax = inf). Shuffled with `seed`.
RaySet shadow_rays(const Scene& scene, const RaySet& primary, const std::vector<Hit>& hits, uint32_t seed);

}  // namespace pt::bench
