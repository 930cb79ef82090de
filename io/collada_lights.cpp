// add_light: the light types and their placement by the node transform.
#include "collada_lights.h"

#include <cmath>

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
    if (std::string_view(t.attribute("profile").value()) == "CGL")
      if (pugi::xml_node area = t.child("area")) return area;
  return {};
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

void add_light(ColladaDocument& doc, pugi::xml_node light, const Mat4& world, Scene& scene) {
  if (pugi::xml_node area = cgl_area(light)) return add_area_light(doc, area, world, scene);

  pugi::xml_node common = light.child("technique_common");
  pugi::xml_node kind = common.first_child();
  std::string_view type = kind ? kind.name() : "";
  if (type == "point") {
    float3 position = world.transform_point({0, 0, 0});
    if (!within_coordinate_limit(position)) doc.fail(kind, "point light lies beyond the coordinate limit 1e15");
    scene.point_lights.push_back({position, read_light_color(doc, kind)});
  } else if (type == "directional") {
    float3 to_light = world.transform_vector({0, 0, 1});
    float len = length(to_light);
    if (!(len > 0.0f) || !std::isfinite(len)) doc.fail(kind, "directional light has a degenerate transform");
    scene.directional_lights.push_back({to_light / len, read_light_color(doc, kind)});
  } else if (type == "ambient") {
    float3 c = read_light_color(doc, kind);
    scene.sky = SkyLight{(scene.sky ? scene.sky->radiance : float3(0.0f)) + c};
  } else if (type == "spot") {
    doc.warn(light, "spot lights are not supported; skipped");
  } else {
    doc.warn(light, "unknown light type" + (type.empty() ? std::string() : " <" + excerpt(type) + ">") + "; skipped");
  }
}

}  // namespace pt
