// The render's camera from the scene, a camera file and the lens flags.
#include "render_camera.h"

#include <cmath>

#include "io/camera_setup.h"

namespace pt::cli {

Camera render_camera(const Options& o, const Scene& scene) {
  const RenderSettings& rs = o.settings;
  Camera c = o.camera_file.empty() ? resolve_camera(scene, rs.width, rs.height, o.cs184_framing)
                                   : resolve_camera(read_camera_settings_file(o.camera_file), rs.width, rs.height);
  if (o.lens_radius) {
    if (!c.thin_lens() && !o.focal_distance) {
      float d = dot(scene.bounds.center() - c.position, -c.to_camera);
      c.focal_distance = std::isfinite(d) && d > 0.0f ? d : 1.0f;  // empty scene or centre behind: 1 unit
    }
    c.lens_radius = *o.lens_radius;
  }
  if (o.focal_distance) c.focal_distance = *o.focal_distance;
  return c;
}

}  // namespace pt::cli
