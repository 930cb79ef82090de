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

CameraDescription read_camera(ColladaDocument& doc, pugi::xml_node camera, const Mat4& world) {
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
  float3 d = world.transform_point({0.0f, 0.0f, -1.0f});
  float len = length(d);
  if (!(len > 0.0f) || !std::isfinite(len)) doc.fail(camera, "camera transform gives no view direction");
  c.view_dir = d / len;
  return c;
}

}  // namespace pt
