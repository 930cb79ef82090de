// add_light: the light types and their placement by the node transform.
#include "collada_lights.h"

#include <cmath>
#include <cstdio>
#include <numbers>

#include "blender_lights.h"

namespace pt {
namespace {

float3 read_light_color(ColladaDocument& doc, pugi::xml_node kind) {
  pugi::xml_node color = kind.child("color");
  if (!color) doc.fail(kind, "has no <color>");
  float3 c = doc.color(color);
  if (c.x < 0 || c.y < 0 || c.z < 0) doc.fail(color, "negative light colour");
  return c;
}

pugi::xml_node cgl_area(pugi::xml_node light) {
  for (pugi::xml_node t : light.child("extra").children("technique"))
    if (ColladaDocument::is_course_profile(t.attribute("profile").value()))
      if (pugi::xml_node area = t.child("area")) return area;
  return {};
}

std::string fmt3(float3 c) {
  char b[96];
  std::snprintf(b, sizeof b, "(%g, %g, %g)", c.x, c.y, c.z);
  return b;
}

void add_area_light(ColladaDocument& doc, pugi::xml_node area, const Mat4& world, Scene& scene) {
  AreaLight l;
  l.radiance = read_light_color(doc, area);
  l.position = world.transform_point({0, 0, 0});
  l.dim_x = world.transform_vector({1, 0, 0});
  l.dim_y = world.transform_vector({0, 1, 0});
  float3 dir = world.transform_vector({0, 0, -1});
  l.area = length(cross(l.dim_x, l.dim_y));
  float dir_len = length(dir);
  if (!(l.area > 0.0f) || !std::isfinite(l.area) || !(dir_len > 0.0f) || !std::isfinite(dir_len))
    doc.fail(area, "area light has zero area or a degenerate transform");
  float3 half_diagonal = abs(l.dim_x * 0.5f) + abs(l.dim_y * 0.5f);
  if (!within_coordinate_limit(l.position + half_diagonal) || !within_coordinate_limit(l.position - half_diagonal))
    doc.fail(area, "area light lies beyond the coordinate limit 1e15");
  l.direction = dir / dir_len;
  scene.area_lights.push_back(l);
}

}  // namespace

std::string add_light(ColladaDocument& doc, pugi::xml_node light, const Mat4& world, Scene& scene, bool blender_units) {
  std::string name = excerpt(light.attribute("name") ? light.attribute("name").value() : light.attribute("id").value());
  if (pugi::xml_node area = cgl_area(light)) {
    add_area_light(doc, area, world, scene);
    return "area light " + name + " (CGL): 1 x 1 square, radiance " + fmt3(scene.area_lights.back().radiance);
  }
  if (blender_units) {
    if (blender_technique(light)) return add_blender_light(doc, light, world, scene);
    doc.warn(light,
             "no `blender` technique: read from technique_common by Cycles' rules (an area light reads as a point "
             "light)");
  }

  pugi::xml_node common = light.child("technique_common");
  pugi::xml_node kind = common.first_child();
  std::string_view type = kind ? kind.name() : "";
  if (type == "point" || (type == "spot" && blender_units)) {
    float3 position = world.transform_point({0, 0, 0});
    if (!within_coordinate_limit(position)) doc.fail(kind, "point light lies beyond the coordinate limit 1e15");
    PointLight p{position, read_light_color(doc, kind)};
    if (!blender_units) {
      scene.point_lights.push_back(p);
      return "point light " + name + ": radiance " + fmt3(p.radiance) + ", no falloff (the course's)";
    }
    p.radiance = p.radiance / (4.0f * std::numbers::pi_v<float>);  // watts to W/sr
    p.flags = PointLight::kInverseSquare;
    if (type == "spot") {
      float angle = doc.scalar(kind.child("falloff_angle"), 180.0f);
      float blend = doc.scalar(kind.child("falloff_exponent"), 0.0f);
      if (!(angle > 0.0f && angle <= 180.0f)) doc.fail(kind, "falloff_angle must be in (0, 180] degrees");
      if (!(blend >= 0.0f && blend <= 1.0f)) doc.fail(kind, "falloff_exponent (Blender's blend) must be in [0, 1]");
      float3 dir = world.transform_vector({0, 0, -1});
      float len = length(dir);
      if (!(len > 0.0f) || !std::isfinite(len)) doc.fail(kind, "spot light has a degenerate transform");
      p.flags |= PointLight::kSpot;
      p.spot_dir = dir / len;
      p.spot_cos_half = std::cos(angle * std::numbers::pi_v<float> / 360.0f);
      p.spot_smooth = (1.0f - p.spot_cos_half) * blend;
    }
    scene.point_lights.push_back(p);
    return std::string(type) + " light " + name + ": intensity " + fmt3(p.radiance) + " W/sr";
  } else if (type == "directional") {
    float3 to_light = world.transform_vector({0, 0, 1});
    float len = length(to_light);
    if (!(len > 0.0f) || !std::isfinite(len)) doc.fail(kind, "directional light has a degenerate transform");
    scene.directional_lights.push_back({to_light / len, read_light_color(doc, kind)});
    return "directional light " + name + ": " + fmt3(scene.directional_lights.back().radiance);
  } else if (type == "ambient") {
    float3 c = read_light_color(doc, kind);
    scene.sky = SkyLight{(scene.sky ? scene.sky->radiance : float3(0.0f)) + c};
    return "ambient light " + name + ": sky radiance " + fmt3(c);
  } else if (type == "spot") {
    doc.warn(light, "spot lights are not supported; skipped");
  } else {
    doc.warn(light, "unknown light type" + (type.empty() ? std::string() : " <" + excerpt(type) + ">") + "; skipped");
  }
  return {};
}

}  // namespace pt
