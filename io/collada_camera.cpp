// read_camera: <perspective> parameters and the course's placement rule.
#include "collada_camera.h"

#include <cmath>
#include <numbers>

namespace pt {
namespace {

constexpr float kDegrees = 180.0f / std::numbers::pi_v<float>;

float read_fov(ColladaDocument& doc, pugi::xml_node e, float fallback) {
  float v = doc.scalar(e, fallback);
  if (!(v > 0.0f && v < 180.0f)) doc.fail(e, "field of view must be between 0 and 180 degrees");
  return v;
}

}  // namespace

CameraDescription read_camera(ColladaDocument& doc, pugi::xml_node camera, const Mat4& world, bool blender_placement) {
  CameraDescription c;
  pugi::xml_node persp = camera.child("optics").child("technique_common").child("perspective");
  if (!persp) {
    doc.warn(camera, "no <perspective> optics; using the default camera");
  } else {
    pugi::xml_node xfov = persp.child("xfov"), yfov = persp.child("yfov"), aspect = persp.child("aspect_ratio");
    c.hfov_deg = read_fov(doc, xfov, 50.0f);
    if (yfov) {
      c.vfov_deg = read_fov(doc, yfov, 35.0f);
    } else if (aspect) {
      float a = doc.scalar(aspect, 1.0f);
      if (!(a > 0.0f)) doc.fail(aspect, "aspect ratio must be positive");
      c.vfov_deg = 2.0f * std::atan(std::tan(c.hfov_deg / 2.0f / kDegrees) / a) * kDegrees;
      if (!(c.vfov_deg > 0.0f && c.vfov_deg < 180.0f))
        doc.fail(aspect, "aspect ratio gives a vertical field of view outside (0, 180) degrees");
    }
    c.near_clip = doc.scalar(persp.child("znear"), c.near_clip);
    c.far_clip = doc.scalar(persp.child("zfar"), c.far_clip);
    if (!(c.near_clip >= 0.0f && c.far_clip > c.near_clip)) doc.fail(persp, "needs 0 <= znear < zfar");
  }
  if (blender_placement) {
    c.placed = true;
    c.position = world.transform_point({0.0f, 0.0f, 0.0f});
    float3 axes[3] = {world.transform_vector({1, 0, 0}), world.transform_vector({0, 1, 0}),
                      world.transform_vector({0, 0, 1})};
    for (float3& a : axes) {
      float len = length(a);
      if (!(len > 0.0f) || !std::isfinite(len) || !within_coordinate_limit(c.position))
        doc.fail(camera, "camera transform is degenerate or beyond the coordinate limit 1e15");
      a = a / len;
    }
    c.screen_x = axes[0];
    c.screen_y = normalize(cross(axes[2], axes[0]));  // orthonormal even if the node shears
    c.to_camera = normalize(cross(c.screen_x, c.screen_y));
    for (pugi::xml_node t : camera.child("extra").children("technique"))
      if (std::string_view(t.attribute("profile").value()) == "blender")
        for (const char* shift : {"shiftx", "shifty"})
          if (doc.scalar(t.child(shift), 0.0f) != 0.0f)
            doc.warn(t.child(shift), "Blender's lens shift is not modelled; rendered without it");
    return c;
  }
  float3 d = world.transform_point({0.0f, 0.0f, -1.0f});
  float len = length(d);
  if (!(len > 0.0f) || !std::isfinite(len)) doc.fail(camera, "camera transform gives no view direction");
  c.view_dir = d / len;
  return c;
}

}  // namespace pt
