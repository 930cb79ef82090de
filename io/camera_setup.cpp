// Camera placement, field-of-view widening and camera settings files.
#include "camera_setup.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>

#include "atomic_file.h"
#include "read_file.h"
#include "scene_error.h"
#include "strict_number.h"

namespace pt {
namespace {

constexpr double kRadians = std::numbers::pi / 180.0;

/// Widens whichever field of view is too narrow for the aspect width/height.
void widen_to_aspect(double& hfov_deg, double& vfov_deg, int width, int height) {
  double th = std::tan(hfov_deg * kRadians / 2), tv = std::tan(vfov_deg * kRadians / 2);
  double target = double(width) / height;
  if (th / tv < target) hfov_deg = 2 * std::atan(tv * target) / kRadians;
  else if (th / tv > target) vfov_deg = 2 * std::atan(th / target) / kRadians;
}

}  // namespace

/// Blender's camera: its node's placement; the sensor's angle spans the
/// image's longer side (Auto sensor fit), the other side by the aspect.
Camera resolve_placed_camera(const CameraDescription& d, int width, int height) {
  Camera c;
  c.position = d.position;
  c.screen_x = d.screen_x;
  c.screen_y = d.screen_y;
  c.to_camera = d.to_camera;
  c.near_clip = d.near_clip;
  c.far_clip = d.far_clip;
  double t = std::tan(double(d.hfov_deg) * kRadians / 2);
  double aspect = double(width) / height;
  c.tan_half_hfov = static_cast<float>(width >= height ? t : t * aspect);
  c.tan_half_vfov = static_cast<float>(width >= height ? t / aspect : t);
  return c;
}

Camera resolve_camera(const Scene& scene, int width, int height, bool cs184_framing) {
  const CameraDescription& d = scene.camera;
  if (d.placed) return resolve_placed_camera(d, width, height);
  BBox b = scene.bounds.empty() ? BBox{float3(-1.0f), float3(1.0f)} : scene.bounds;
  float3 target = b.center();
  float distance = 1.5f * length(b.extent());

  Camera c;
  float3 to_camera = d.view_dir * distance;
  c.position = target + to_camera;
  float3 up{0.0f, 1.0f, 0.0f};
  if (length(cross(up, to_camera)) == 0.0f) up = {0.0f, 0.0f, -1.0f};  // looking straight down or up
  c.screen_x = normalize(cross(up, to_camera));
  c.screen_y = normalize(cross(to_camera, c.screen_x));
  c.to_camera = normalize(to_camera);
  c.near_clip = d.near_clip;
  c.far_clip = d.far_clip;

  double hfov = d.hfov_deg, vfov = d.vfov_deg;
  if (cs184_framing) {
    widen_to_aspect(hfov, vfov, 800, 600);
    double screen_dist = 600.0 / (2.0 * std::tan(vfov * kRadians / 2));
    c.tan_half_hfov = static_cast<float>(width / (2.0 * screen_dist));
    c.tan_half_vfov = static_cast<float>(height / (2.0 * screen_dist));
  } else {
    widen_to_aspect(hfov, vfov, width, height);
    c.tan_half_hfov = static_cast<float>(std::tan(hfov * kRadians / 2));
    c.tan_half_vfov = static_cast<float>(std::tan(vfov * kRadians / 2));
  }
  return c;
}

Camera resolve_camera(const CameraSettingsFile& f, int width, int height) {
  Camera c;
  c.position = f.position;
  c.screen_x = {f.c2w[0][0], f.c2w[1][0], f.c2w[2][0]};
  c.screen_y = {f.c2w[0][1], f.c2w[1][1], f.c2w[2][1]};
  c.to_camera = {f.c2w[0][2], f.c2w[1][2], f.c2w[2][2]};
  c.near_clip = f.near_clip;
  c.far_clip = f.far_clip;
  double hfov = f.hfov_deg, vfov = f.vfov_deg;
  widen_to_aspect(hfov, vfov, width, height);
  c.tan_half_hfov = static_cast<float>(std::tan(hfov * kRadians / 2));
  c.tan_half_vfov = static_cast<float>(std::tan(vfov * kRadians / 2));
  if (f.lens_radius > 0) {
    c.lens_radius = f.lens_radius;
    c.focal_distance = f.focal_distance;
  }
  return c;
}

CameraSettingsFile read_camera_settings_file(const std::filesystem::path& path) {
  std::istringstream in(read_regular_file(path, "camera file", 1u << 20));
  CameraSettingsFile f;
  auto read = [&](const char* name, float& v) {
    std::string tok;
    if (!(in >> tok)) throw InputError(path.string() + ": camera file ends before " + name);
    if (parse_float(tok, v) != Number::kOk || !std::isfinite(v))
      throw InputError(path.string() + ": camera file field " + name + " is not a finite number: \"" + excerpt(tok) +
                       "\"");
  };
  read("hFov", f.hfov_deg);
  read("vFov", f.vfov_deg);
  read("aspect", f.aspect);
  read("nClip", f.near_clip);
  read("fClip", f.far_clip);
  read("pos.x", f.position.x);
  read("pos.y", f.position.y);
  read("pos.z", f.position.z);
  read("target.x", f.target.x);
  read("target.y", f.target.y);
  read("target.z", f.target.z);
  read("phi", f.phi);
  read("theta", f.theta);
  read("r", f.r);
  read("minR", f.min_r);
  read("maxR", f.max_r);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) read("c2w", f.c2w[i][j]);
  read("screenW", f.screen_w);
  read("screenH", f.screen_h);
  read("screenDist", f.screen_dist);
  read("focalDistance", f.focal_distance);
  read("lensRadius", f.lens_radius);
  if (std::string problem = camera_settings_problem(f); !problem.empty())
    throw InputError(path.string() + ": camera file " + problem);
  return f;
}

std::string camera_settings_problem(const CameraSettingsFile& f) {
  if (!(f.hfov_deg > 0 && f.hfov_deg < 180 && f.vfov_deg > 0 && f.vfov_deg < 180))
    return "fields of view must be between 0 and 180 degrees";
  if (!(f.near_clip >= 0 && f.far_clip > f.near_clip)) return "needs 0 <= nClip < fClip";
  if (!(f.lens_radius >= 0) || (f.lens_radius > 0 && !(f.focal_distance > 0)))
    return "needs lensRadius >= 0, and focalDistance > 0 when lensRadius > 0";
  float3 cols[3] = {{f.c2w[0][0], f.c2w[1][0], f.c2w[2][0]},
                    {f.c2w[0][1], f.c2w[1][1], f.c2w[2][1]},
                    {f.c2w[0][2], f.c2w[1][2], f.c2w[2][2]}};
  for (const float3& col : cols)
    if (!(std::fabs(length(col) - 1.0f) <= 1e-3f)) return "c2w columns must be unit vectors";
  return {};
}

CameraSettingsFile camera_settings_of(const Camera& c, int width, int height) {
  CameraSettingsFile f;
  f.hfov_deg = static_cast<float>(2 * std::atan(c.tan_half_hfov) / kRadians);
  f.vfov_deg = static_cast<float>(2 * std::atan(c.tan_half_vfov) / kRadians);
  f.aspect = static_cast<float>(double(width) / height);
  f.near_clip = c.near_clip;
  f.far_clip = c.far_clip;
  f.position = c.position;
  f.target = c.position - c.to_camera;
  f.phi = std::acos(std::clamp(c.to_camera.y, -1.0f, 1.0f));
  f.theta = std::atan2(c.to_camera.x, c.to_camera.z);
  f.r = 1;
  f.min_r = 0;
  f.max_r = 1e30f;
  float3 cols[3] = {c.screen_x, c.screen_y, c.to_camera};
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) f.c2w[i][j] = cols[j][i];
  f.screen_w = static_cast<float>(width);
  f.screen_h = static_cast<float>(height);
  f.screen_dist = static_cast<float>(height / (2.0 * c.tan_half_vfov));
  f.focal_distance = c.thin_lens() ? c.focal_distance : 0.0f;
  f.lens_radius = c.lens_radius;
  return f;
}

std::string format_camera_settings(const CameraSettingsFile& f) {
  std::ostringstream o;
  o.precision(9);
  o << f.hfov_deg << " " << f.vfov_deg << " " << f.aspect << " " << f.near_clip << " " << f.far_clip << "\n";
  o << f.position.x << " " << f.position.y << " " << f.position.z << " " << f.target.x << " " << f.target.y << " "
    << f.target.z << "\n";
  o << f.phi << " " << f.theta << " " << f.r << " " << f.min_r << " " << f.max_r << "\n";
  for (int i = 0; i < 3; ++i) o << f.c2w[i][0] << " " << f.c2w[i][1] << " " << f.c2w[i][2] << "\n";
  o << f.screen_w << " " << f.screen_h << " " << f.screen_dist << "\n"
    << f.focal_distance << " " << f.lens_radius << "\n";
  return o.str();
}

void write_camera_settings_file(const std::filesystem::path& path, const Camera& c, int width, int height) {
  write_camera_settings_file(path, camera_settings_of(c, width, height));
}

void write_camera_settings_file(const std::filesystem::path& path, const CameraSettingsFile& f) {
  write_file_atomically(path, format_camera_settings(f));
}

}  // namespace pt
