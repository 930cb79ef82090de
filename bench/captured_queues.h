// The queues a real render traces, as benchmark ray sets: a wavefront render
// of the scene on one thread (so that the queues come in the render's order),
// its bounce queues (closest hit) and its shadow queues (occlusion) of depths
// 1 to 4, each kept whole, up to a number of rays per set.
#pragma once

#include <cstddef>

#include "bvh/scene_bvh4.h"
#include "kernels/scene/scene.h"
#include "ray_sets.h"

namespace pt::bench {

struct CaptureSettings {
  int width = 128, height = 96;  ///< the scene's camera, this many pixels
  int samples = 16;              ///< -s: a wave of 8192 paths is 512 pixels' samples
  int light_samples = 4;         ///< -l
  int max_depth = 5;             ///< -m
  size_t max_rays = 1 << 19;     ///< per set: whole queues until this many rays
};

struct CapturedQueues {
  RaySet bounce;  ///< "bounce_queues"
  RaySet shadow;  ///< "shadow_queues"
};

/// Renders the scene through `bvh` with the wavefront's default sampler and
/// estimators and collects its queues.
CapturedQueues capture_queues(const Scene& scene, const SceneBvh4& bvh, const CaptureSettings& settings = {});

}  // namespace pt::bench
