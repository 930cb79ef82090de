// scene_invariant_violation and message_violation.
#include "scene_invariants.h"

#include <cmath>

namespace pt::fuzz {
namespace {

bool colour_ok(float3 c) { return is_finite(c) && c.x >= 0 && c.y >= 0 && c.z >= 0; }
bool unit(float3 n) { return is_finite(n) && std::fabs(length(n) - 1.0f) < 1e-3f; }

std::string geometry_violation(const Scene& s) {
  if (s.normals.size() != s.positions.size()) return "normals and positions differ in count";
  if (s.triangle_material.size() != s.triangles.size()) return "triangle_material and triangles differ in count";
  size_t light_triangles = 0;
  for (const AreaLight& l : s.area_lights) light_triangles += l.shape == AreaShape::kEllipse ? kEllipseSegments : 2;
  if (s.mesh_triangle_count + light_triangles != s.triangles.size())
    return "triangle count is not mesh triangles + 2 per parallelogram and kEllipseSegments per elliptical light";
  for (const float3& p : s.positions)
    if (!is_finite(p)) return "non-finite position";
  for (const float3& n : s.normals)
    if (!unit(n)) return "normal is not unit length";
  for (size_t i = 0; i < s.triangles.size(); ++i) {
    const TriangleIndices& t = s.triangles[i];
    if (t.v0 >= s.positions.size() || t.v1 >= s.positions.size() || t.v2 >= s.positions.size())
      return "triangle " + std::to_string(i) + " indexes past the positions";
    if (s.triangle_material[i] >= s.materials.size()) return "triangle material out of range";
  }
  for (const Sphere& sp : s.spheres) {
    if (!is_finite(sp.center) || !(sp.radius > 0.0f) || !std::isfinite(sp.radius)) return "degenerate sphere";
    if (sp.material >= s.materials.size()) return "sphere material out of range";
  }
  if (!s.bounds.empty() && !std::isfinite(1.5f * length(s.bounds.extent()) + length(s.bounds.center())))
    return "scene bounds too large for the camera rule";
  return {};
}

std::string light_violation(const Scene& s) {
  for (const Material& m : s.materials) {
    if (!colour_ok(m.albedo) || !colour_ok(m.emission)) return "material colour negative or non-finite";
    if (m.area_light >= static_cast<int32_t>(s.area_lights.size())) return "material names a missing area light";
  }
  for (const AreaLight& l : s.area_lights)
    if (!colour_ok(l.radiance) || !(l.area > 0.0f) || !std::isfinite(l.area) || !unit(l.direction) ||
        !is_finite(l.position) || !is_finite(l.dim_x) || !is_finite(l.dim_y))
      return "degenerate area light";
  for (const PointLight& l : s.point_lights) {
    if (!colour_ok(l.radiance) || !is_finite(l.position)) return "bad point light";
    if (!(l.radius >= 0.0f) || !std::isfinite(l.radius)) return "bad point light radius";
    if ((l.flags & PointLight::kSpot) && (!unit(l.spot_dir) || !(l.spot_cos_half >= -1.0f && l.spot_cos_half < 1.0f) ||
                                          !(l.spot_smooth >= 0.0f) || !std::isfinite(l.spot_smooth)))
      return "bad spot cone";
  }
  for (const DirectionalLight& l : s.directional_lights)
    if (!colour_ok(l.radiance) || !unit(l.to_light)) return "bad directional light";
  if (s.sky && !colour_ok(s.sky->radiance)) return "bad sky";
  const CameraDescription& c = s.camera;
  if (!(c.hfov_deg > 0 && c.hfov_deg < 180 && c.vfov_deg > 0 && c.vfov_deg < 180)) return "bad field of view";
  if (!(c.near_clip >= 0 && c.far_clip > c.near_clip) || !std::isfinite(c.far_clip)) return "bad clip range";
  if (!unit(c.view_dir)) return "camera view direction is not unit length";
  if (c.placed && (!is_finite(c.position) || !unit(c.screen_x) || !unit(c.screen_y) || !unit(c.to_camera)))
    return "placed camera is not finite or its basis not unit";
  return {};
}

}  // namespace

std::string scene_invariant_violation(const Scene& s) {
  std::string v = geometry_violation(s);
  return v.empty() ? light_violation(s) : v;
}

std::string message_violation(const std::string& message, const std::string& label) {
  if (message.rfind(label, 0) != 0) return "does not start with the file name";
  if (message.size() > 1000) return "longer than 1000 bytes";
  for (char c : message)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) return "contains a control character";
  return {};
}

}  // namespace pt::fuzz
