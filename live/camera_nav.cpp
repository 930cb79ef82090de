// Orbit, pan, zoom and look-at on the camera file's fields, in double
// precision, stored as the file's floats.
#include "camera_nav.h"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace pt::live {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kMinPhi = 1e-4;  ///< keeps the camera off the poles, where the +Y basis degenerates

struct D3 {
  double x, y, z;
};
D3 d3(float3 v) { return {v.x, v.y, v.z}; }
float3 f3(const D3& v) { return {float(v.x), float(v.y), float(v.z)}; }
D3 cross(const D3& a, const D3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
D3 unit(const D3& a) {
  double n = std::sqrt(a.x * a.x + a.y * a.y + a.z * a.z);
  return {a.x / n, a.y / n, a.z / n};
}

void set_column(ViewCamera& v, int column, const D3& c) {
  v.c2w[0][column] = float(c.x);
  v.c2w[1][column] = float(c.y);
  v.c2w[2][column] = float(c.z);
}
D3 column(const ViewCamera& v, int column) { return {v.c2w[0][column], v.c2w[1][column], v.c2w[2][column]}; }

/// Position and +Y basis from target, phi, theta and r (the course's compute_position).
void place_on_sphere(ViewCamera& v) {
  double sp = std::sin(double(v.phi)), cp = std::cos(double(v.phi));
  D3 dir{sp * std::sin(double(v.theta)), cp, sp * std::cos(double(v.theta))};
  D3 t = d3(v.target);
  v.position = f3({t.x + v.r * dir.x, t.y + v.r * dir.y, t.z + v.r * dir.z});
  D3 screen_x = unit(cross({0.0, 1.0, 0.0}, dir));
  D3 screen_y = unit(cross(dir, screen_x));
  set_column(v, 0, screen_x);
  set_column(v, 1, screen_y);
  set_column(v, 2, dir);
}

/// phi and theta of the unit direction from the target to the camera.
void set_angles(ViewCamera& v, const D3& dir) {
  v.phi = float(std::acos(std::clamp(dir.y, -1.0, 1.0)));
  v.theta = float(std::atan2(dir.x, dir.z));
}

/// The file keeps fields of view in degrees, as floats: of the floats near
/// the converted angles, takes a pair that resolves to `c`'s tangents exactly
/// when there is one (so the unmoved view is the command line's camera to the
/// bit, and so is its saved file).
void keep_tangents(ViewCamera& v, const Camera& c, int width, int height) {
  auto ulps = [](float x, int n) {  // x moved by n floats
    for (; n > 0; --n) x = std::nextafter(x, 180.0f);
    for (; n < 0; ++n) x = std::nextafter(x, 0.0f);
    return x;
  };
  const float h0 = v.hfov_deg, v0 = v.vfov_deg;
  for (int i = 0; i <= 32; ++i)
    for (int j = 0; j <= 32; ++j) {
      v.hfov_deg = ulps(h0, i % 2 ? (i + 1) / 2 : -i / 2);  // 0, 1, -1, 2, -2, ...
      v.vfov_deg = ulps(v0, j % 2 ? (j + 1) / 2 : -j / 2);
      const Camera r = resolve_camera(v, width, height);
      if (r.tan_half_hfov == c.tan_half_hfov && r.tan_half_vfov == c.tan_half_vfov) return;
    }
  v.hfov_deg = h0;
  v.vfov_deg = v0;
}

}  // namespace

NavLimits nav_limits(const BBox& b) {
  float diagonal = b.empty() ? 1.0f : length(b.extent());
  if (!(diagonal > 0.0f) || !std::isfinite(diagonal)) diagonal = 1.0f;
  const float3 centre = b.empty() || !std::isfinite(length(b.center())) ? float3{} : b.center();
  return {1e-3f * diagonal, 100.0f * diagonal, centre, 100.0f * diagonal};
}

ViewCamera view_from_camera(const Camera& c, int width, int height, float3 centre, const NavLimits& limits) {
  ViewCamera v = camera_settings_of(c, width, height);
  D3 to_camera = d3(c.to_camera);
  D3 to_centre = d3(centre - c.position);
  double ahead = -(to_centre.x * to_camera.x + to_centre.y * to_camera.y + to_centre.z * to_camera.z);
  double r = std::isfinite(ahead) ? std::clamp(ahead, double(limits.min_r), double(limits.max_r)) : limits.min_r;
  D3 p = d3(c.position);
  v.target = f3({p.x - r * to_camera.x, p.y - r * to_camera.y, p.z - r * to_camera.z});
  v.r = float(r);
  v.min_r = limits.min_r;
  v.max_r = limits.max_r;
  set_angles(v, unit(to_camera));
  keep_tangents(v, c, width, height);
  return v;
}

ViewCamera orbit(const ViewCamera& v, double dx, double dy, int width, int height) {
  ViewCamera o = v;
  o.phi = float(std::clamp(double(v.phi) - dy * kPi / height, kMinPhi, kPi - kMinPhi));
  o.theta = float(std::remainder(double(v.theta) - dx * kPi / width, 2 * kPi));
  place_on_sphere(o);
  return o;
}

ViewCamera pan(const ViewCamera& v, double dx, double dy, float tan_half_vfov, int height, const NavLimits& limits) {
  ViewCamera o = v;
  double scale = 2.0 * double(v.r) * tan_half_vfov / height;  // world units per pixel at the target's depth
  D3 sx = column(v, 0), sy = column(v, 1);
  D3 move{-dx * scale * sx.x + dy * scale * sy.x, -dx * scale * sx.y + dy * scale * sy.y,
          -dx * scale * sx.z + dy * scale * sy.z};
  D3 p = d3(v.position), t = d3(v.target), c = d3(limits.centre);
  D3 away{t.x + move.x - c.x, t.y + move.y - c.y, t.z + move.z - c.z};  // the moved target from the centre
  const double far = std::sqrt(away.x * away.x + away.y * away.y + away.z * away.z);
  if (far > limits.reach) {  // stop at the reach: the target on its sphere, the camera moved as much
    const double k = limits.reach / far;
    move = {c.x + away.x * k - t.x, c.y + away.y * k - t.y, c.z + away.z * k - t.z};
  }
  o.position = f3({p.x + move.x, p.y + move.y, p.z + move.z});
  o.target = f3({t.x + move.x, t.y + move.y, t.z + move.z});
  return o;
}

ViewCamera zoom(const ViewCamera& v, double steps, const NavLimits& limits) {
  ViewCamera o = v;
  double r = std::clamp(double(v.r) * std::pow(1.1, steps), double(limits.min_r), double(limits.max_r));
  D3 dir = column(v, 2), t = d3(v.target);
  o.r = float(r);
  o.position = f3({t.x + r * dir.x, t.y + r * dir.y, t.z + r * dir.z});
  return o;
}

ViewCamera look_at(const ViewCamera& v, float3 position, float3 target, const NavLimits& limits) {
  ViewCamera o = v;
  D3 p = d3(position), t = d3(target);
  D3 offset{p.x - t.x, p.y - t.y, p.z - t.z};
  double r = std::sqrt(offset.x * offset.x + offset.y * offset.y + offset.z * offset.z);
  o.target = target;
  o.r = float(std::clamp(r, double(limits.min_r), double(limits.max_r)));
  set_angles(o, unit(offset));
  o.phi = float(std::clamp(double(o.phi), kMinPhi, kPi - kMinPhi));
  place_on_sphere(o);
  return o;
}

std::string look_at_problem(float3 position, float3 target, const NavLimits& limits) {
  D3 p = d3(position), t = d3(target);
  D3 offset{p.x - t.x, p.y - t.y, p.z - t.z};
  double r = std::sqrt(offset.x * offset.x + offset.y * offset.y + offset.z * offset.z);
  if (!(r >= limits.min_r && r <= limits.max_r))
    return "position and target must be from " + std::to_string(limits.min_r) + " to " + std::to_string(limits.max_r) +
           " apart, got " + std::to_string(r);
  if (!(length(target - limits.centre) <= limits.reach))
    return "the target must lie within " + std::to_string(limits.reach) + " of the scene's centre, got " +
           std::to_string(length(target - limits.centre));
  const double phi = std::acos(std::clamp(offset.y / r, -1.0, 1.0));
  if (phi < kMinPhi || phi > kPi - kMinPhi)
    return "the camera must not be straight above or below its target (the view keeps +Y up)";
  return {};
}

ViewCamera fit_screen(const ViewCamera& v, int width, int height) {
  const CameraSettingsFile f = camera_settings_of(resolve_camera(v, width, height), width, height);
  ViewCamera o = v;
  o.aspect = f.aspect;
  o.screen_w = f.screen_w;
  o.screen_h = f.screen_h;
  o.screen_dist = f.screen_dist;
  return o;
}

bool project_to_pixel(const Camera& c, int width, int height, float3 p, float& px, float& py) {
  D3 d = d3(p - c.position), sx = d3(c.screen_x), sy = d3(c.screen_y), tc = d3(c.to_camera);
  double depth = -(d.x * tc.x + d.y * tc.y + d.z * tc.z);
  if (!(depth > 0.0)) return false;
  double x = (d.x * sx.x + d.y * sx.y + d.z * sx.z) / (depth * c.tan_half_hfov);
  double y = (d.x * sy.x + d.y * sy.y + d.z * sy.z) / (depth * c.tan_half_vfov);
  px = float((x + 1.0) * 0.5 * width);
  py = float((1.0 - (y + 1.0) * 0.5) * height);
  return true;
}

}  // namespace pt::live
