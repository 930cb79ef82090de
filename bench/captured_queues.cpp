// capture_queues: one render with the wavefront's queue hook.
#include "captured_queues.h"

#include "io/camera_setup.h"
#include "wavefront/engines.h"

namespace pt::bench {
namespace {

/// Appends queues to a set until the first that does not fit.
struct Keeper {
  RaySet& set;
  size_t max_rays;
  bool full = false;
  void operator()(std::span<const Ray> rays) {
    full = full || set.rays.size() + rays.size() > max_rays;
    if (full) return;
    set.rays.insert(set.rays.end(), rays.begin(), rays.end());
    set.queue_ends.push_back(set.rays.size());
  }
};

}  // namespace

CapturedQueues capture_queues(const Scene& scene, const SceneBvh4& bvh, const CaptureSettings& c) {
  CapturedQueues out{{"bounce_queues", false, {}, {}}, {"shadow_queues", true, {}, {}}};
  RenderSettings rs;
  rs.width = c.width;
  rs.height = c.height;
  rs.samples_per_pixel = c.samples;
  rs.light_samples = c.light_samples;
  rs.max_depth = c.max_depth;
  rs.threads = 1;
  const Camera camera = resolve_camera(scene, rs.width, rs.height);
  Keeper bounce{out.bounce, c.max_rays}, shadow{out.shadow, c.max_rays};
  wf::WavefrontOptions options;
  options.capture = [&](wf::QueueKind kind, uint32_t depth, std::span<const Ray> rays) {
    if (depth < 1 || depth > 4) return;
    if (kind == wf::QueueKind::kBounce) bounce(rays);
    else if (kind == wf::QueueKind::kShadow) shadow(rays);
  };
  wf::render_wavefront(scene, camera, rs, wf::Tracing{.bvh4 = &bvh}, options);
  return out;
}

}  // namespace pt::bench
