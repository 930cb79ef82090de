// add_blender_light: Blender's light types and Cycles' conversion of power.
//   point, spot: radiant intensity I = P / (4 pi) per watt, arriving as I / d^2;
//   sun: strength = irradiance (W / m^2) on a surface facing it;
//   area: radiance L = P / (4 A) (Cycles 3.x: eval factor 0.25 / area).
#include "blender_lights.h"

#include <cmath>
#include <numbers>

namespace pt {
namespace {

constexpr float kMaxEnergy = 1e12f;  // watts (W / m^2 for a sun): far above any real light
constexpr float kMaxSize = 1e6f;     // metres, before the node's scale

std::string fmt(float v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}

/// A number of the technique, or `fallback` when absent; fails outside [lo, hi].
float parameter(ColladaDocument& doc, pugi::xml_node tech, const char* name, float fallback, float lo, float hi) {
  pugi::xml_node e = tech.child(name);
  if (!e) return fallback;
  float v = doc.scalar(e, fallback);
  if (!(v >= lo && v <= hi))
    doc.fail(e, std::string(name) + " " + fmt(v) + " is outside [" + fmt(lo) + ", " + fmt(hi) + "]");
  return v;
}

/// The light's colour (red, green, blue of the technique; else technique_common's colour over the energy).
float3 light_colour(ColladaDocument& doc, pugi::xml_node light, pugi::xml_node tech, float energy) {
  if (tech.child("red") || tech.child("green") || tech.child("blue"))
    return {parameter(doc, tech, "red", 1.0f, 0.0f, 1e6f), parameter(doc, tech, "green", 1.0f, 0.0f, 1e6f),
            parameter(doc, tech, "blue", 1.0f, 0.0f, 1e6f)};
  pugi::xml_node color = light.child("technique_common").first_child().child("color");
  if (!color || energy == 0.0f) return float3(1.0f);
  float3 c = doc.color(color);
  if (c.x < 0 || c.y < 0 || c.z < 0) doc.fail(color, "negative light colour");
  return c / energy;
}

float3 unit_axis(ColladaDocument& doc, pugi::xml_node where, const Mat4& world, float3 local) {
  float3 d = world.transform_vector(local);
  float len = length(d);
  if (!(len > 0.0f) || !std::isfinite(len)) doc.fail(where, "light has a degenerate transform");
  return d / len;
}

std::string rgb(float3 c) { return "(" + fmt(c.x) + ", " + fmt(c.y) + ", " + fmt(c.z) + ")"; }

}  // namespace

pugi::xml_node blender_technique(pugi::xml_node element) {
  for (pugi::xml_node t : element.child("extra").children("technique"))
    if (std::string_view(t.attribute("profile").value()) == "blender") return t;
  return {};
}

std::string add_blender_light(ColladaDocument& doc, pugi::xml_node light, const Mat4& world, Scene& scene) {
  pugi::xml_node tech = blender_technique(light);
  pugi::xml_node type_node = tech.child("type");
  if (!type_node) doc.fail(tech, "has no <type>");
  float type = doc.scalar(type_node, 0.0f);
  float energy = parameter(doc, tech, "energy", 1.0f, 0.0f, kMaxEnergy);
  float3 colour = light_colour(doc, light, tech, energy);
  float3 power = colour * energy;
  float3 position = world.transform_point({0, 0, 0});
  if (!within_coordinate_limit(position)) doc.fail(light, "light lies beyond the coordinate limit 1e15");
  std::string name = excerpt(light.attribute("name") ? light.attribute("name").value() : light.attribute("id").value());

  if (type == 0.0f || type == 2.0f) {  // point, spot
    PointLight p;
    p.position = position;
    p.radiance = power / (4.0f * kPi);
    p.flags = PointLight::kInverseSquare;
    p.radius = parameter(doc, tech, "area_size", 0.0f, 0.0f, kMaxSize);
    std::string info = (type == 0.0f ? "point light " : "spot light ") + name + ": " + fmt(energy) + " W, colour " +
                       rgb(colour) + ", intensity " + rgb(p.radiance) + " W/sr, radius " + fmt(p.radius);
    if (type == 2.0f) {
      float size_deg = parameter(doc, tech, "spotsize", 45.0f, 0.0f, 180.0f);
      if (!(size_deg > 0.0f)) doc.fail(tech.child("spotsize"), "spotsize must be above 0 degrees");
      float blend = parameter(doc, tech, "spotblend", 0.15f, 0.0f, 1.0f);
      p.flags |= PointLight::kSpot;
      p.spot_dir = unit_axis(doc, light, world, {0, 0, -1});
      p.spot_cos_half = std::cos(size_deg * kPi / 360.0f);
      p.spot_smooth = (1.0f - p.spot_cos_half) * blend;
      info += ", cone " + fmt(size_deg) + " degrees, blend " + fmt(blend);
    }
    scene.point_lights.push_back(p);
    return info;
  }
  if (type == 1.0f) {  // sun
    float3 to_light = unit_axis(doc, light, world, {0, 0, 1});
    scene.directional_lights.push_back({to_light, power});
    doc.warn(tech, "a sun's angle is not in Blender's export: rendered as a sun of angle 0 (sharp shadows)");
    return "sun " + name + ": strength " + fmt(energy) + " W/m^2, colour " + rgb(colour) + ", angle 0 (not exported)";
  }
  if (type == 4.0f) {  // area
    float shape = parameter(doc, tech, "area_shape", 0.0f, 0.0f, 5.0f);
    bool square = shape == 0.0f || shape == 4.0f;  // square, disk: one size
    if (shape != 0.0f && shape != 1.0f && shape != 4.0f && shape != 5.0f)
      doc.fail(tech.child("area_shape"),
               "unknown area shape " + fmt(shape) + " (0 square, 1 rectangle, 4 disk, 5 ellipse)");
    float sx = parameter(doc, tech, "area_size", 0.25f, 0.0f, kMaxSize);
    float sy = square ? sx : parameter(doc, tech, "area_sizey", 0.25f, 0.0f, kMaxSize);
    AreaLight a;
    a.shape = shape >= 4.0f ? AreaShape::kEllipse : AreaShape::kParallelogram;
    a.position = position;
    a.dim_x = world.transform_vector({sx, 0, 0});
    a.dim_y = world.transform_vector({0, sy, 0});
    a.direction = unit_axis(doc, light, world, {0, 0, -1});
    a.area = length(cross(a.dim_x, a.dim_y)) * (a.shape == AreaShape::kEllipse ? kPi / 4.0f : 1.0f);
    if (!(a.area > 0.0f) || !std::isfinite(a.area))
      doc.fail(tech, "area light has zero area or a degenerate transform");
    float3 half = abs(a.dim_x * 0.5f) + abs(a.dim_y * 0.5f);
    if (!within_coordinate_limit(position + half) || !within_coordinate_limit(position - half))
      doc.fail(tech, "area light lies beyond the coordinate limit 1e15");
    a.radiance = power * (0.25f / a.area);
    if (!std::isfinite(max_component(a.radiance))) doc.fail(tech, "area light's radiance overflows");
    scene.area_lights.push_back(a);
    doc.warn({},
             "area lights are opaque from behind here (a black surface), while Cycles' lights are transparent: "
             "what faces a light's back (a ceiling above a hanging light) is darker (docs/blender_scenes.md)");
    static const char* kShapes[] = {"square", "rectangle", "", "", "disk", "ellipse"};
    return std::string("area light ") + name + ": " + kShapes[static_cast<int>(shape)] + " " + fmt(sx) + " x " +
           fmt(sy) + " m, " + fmt(energy) + " W, colour " + rgb(colour) + ", radiance " + rgb(a.radiance) +
           " W/(m^2 sr)";
  }
  doc.fail(type_node, "unknown Blender light type " + fmt(type) + " (0 point, 1 sun, 2 spot, 4 area)");
}

}  // namespace pt
