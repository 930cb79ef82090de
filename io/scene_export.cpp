// scene_to_json, with nlohmann::json.
#include "scene_export.h"

#include <nlohmann/json.hpp>

namespace pt {
namespace {

using nlohmann::json;

json vec(const float3& v) { return json::array({v.x, v.y, v.z}); }

const char* kind_name(MaterialKind k) {
  switch (k) {
    case MaterialKind::kDiffuse: return "diffuse";
    case MaterialKind::kMirror: return "mirror";
    case MaterialKind::kGlass: return "glass";
    case MaterialKind::kRefraction: return "refraction";
    case MaterialKind::kMicrofacet: return "microfacet";
  }
  return "unknown";
}

json material(const Material& m) {
  json j = {{"kind", kind_name(m.kind)},
            {"albedo", vec(m.albedo)},
            {"emission", vec(m.emission)},
            {"one_sided", (m.flags & Material::kOneSided) != 0},
            {"area_light", m.area_light}};
  if (m.kind == MaterialKind::kGlass || m.kind == MaterialKind::kRefraction) {
    j["ior"] = m.ior;
    j["transmittance"] = vec(m.transmittance);
  }
  if (m.kind == MaterialKind::kMicrofacet) {
    j["alpha"] = m.alpha;
    j["eta"] = vec(m.eta);
    j["k"] = vec(m.k);
  }
  return j;
}

}  // namespace

std::string scene_to_json(const Scene& s, const Camera& c, int width, int height) {
  json positions = json::array(), normals = json::array(), triangles = json::array();
  for (const float3& p : s.positions) positions.insert(positions.end(), {p.x, p.y, p.z});
  for (const float3& n : s.normals) normals.insert(normals.end(), {n.x, n.y, n.z});
  for (size_t i = 0; i < s.triangles.size(); ++i) {
    const TriangleIndices& t = s.triangles[i];
    triangles.insert(triangles.end(), {t.v0, t.v1, t.v2, s.triangle_material[i]});
  }
  json spheres = json::array(), materials = json::array(), area = json::array(), points = json::array(),
       directional = json::array();
  for (const Sphere& sp : s.spheres)
    spheres.push_back({{"centre", vec(sp.center)}, {"radius", sp.radius}, {"material", sp.material}});
  for (const Material& m : s.materials) materials.push_back(material(m));
  for (const AreaLight& l : s.area_lights)
    area.push_back({{"centre", vec(l.position)},
                    {"dim_x", vec(l.dim_x)},
                    {"dim_y", vec(l.dim_y)},
                    {"direction", vec(l.direction)},
                    {"radiance", vec(l.radiance)},
                    {"shape", l.shape == AreaShape::kEllipse ? "ellipse" : "parallelogram"}});
  for (const PointLight& l : s.point_lights)
    points.push_back({{"position", vec(l.position)},
                      {"radiance", vec(l.radiance)},
                      {"inverse_square", (l.flags & PointLight::kInverseSquare) != 0},
                      {"radius", l.radius},
                      {"spot", (l.flags & PointLight::kSpot) != 0},
                      {"spot_dir", vec(l.spot_dir)},
                      {"spot_cos_half", l.spot_cos_half},
                      {"spot_smooth", l.spot_smooth}});
  for (const DirectionalLight& l : s.directional_lights)
    directional.push_back({{"to_light", vec(l.to_light)}, {"radiance", vec(l.radiance)}});
  json doc = {
      {"scene", s.name},
      {"width", width},
      {"height", height},
      {"camera",
       {{"position", vec(c.position)},
        {"screen_x", vec(c.screen_x)},
        {"screen_y", vec(c.screen_y)},
        {"to_camera", vec(c.to_camera)},
        {"tan_half_hfov", c.tan_half_hfov},
        {"tan_half_vfov", c.tan_half_vfov},
        {"near_clip", c.near_clip},
        {"far_clip", c.far_clip},
        {"lens_radius", c.lens_radius},
        {"focal_distance", c.focal_distance}}},
      {"positions", positions},
      {"normals", normals},
      {"triangles", triangles},
      {"mesh_triangle_count", s.mesh_triangle_count},
      {"spheres", spheres},
      {"materials", materials},
      {"area_lights", area},
      {"point_lights", points},
      {"directional_lights", directional},
      {"sky", s.sky ? vec(s.sky->radiance) : json(nullptr)},
      {"environment_map", s.environment != nullptr},
  };
  return doc.dump() + "\n";
}

}  // namespace pt
