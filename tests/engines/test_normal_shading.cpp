// Normal shading (--normals): a pixel shows n * 0.5 + 0.5 of the stored
// shading normal at the point it sees (interpolated and normalised on meshes,
// not turned towards the viewer), black where the ray misses, with no light in
// the scene. Cameras with a 1e-6 field of view make "the point a pixel sees"
// exact, so the colours are checked to float precision, for every engine:
// nothing is estimated, so any error above 1e-5 relative fails, always.
#include <string>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "support/film_checks.h"
#include "support/scene_builders.h"

namespace pt {
namespace {

constexpr float kTiny = 1e-6f;

RenderSettings normal_settings() {
  RenderSettings rs = test::fixed_settings(4, 4, 4);
  rs.shading = ShadingMode::kNormals;
  return rs;
}

float3 colour_of(float3 n) { return n * 0.5f + float3(0.5f); }

// A triangle with three different vertex normals, seen at barycentrics
// (u, v) = (0.2, 0.3) from the front and from the back (the stored normal
// either way), and a ray that misses everything.
TEST(NormalShading, InterpolatedMeshNormalFromBothSides) {
  Scene s;
  const float3 p0{-1, 0, -1}, p1{1, 0, -1}, p2{0, 0, 1};
  const float3 n0 = normalize(float3{0.2f, 1, 0}), n1 = normalize(float3{-0.5f, 1, 0.3f});
  const float3 n2 = normalize(float3{0, 1, -0.6f});
  s.positions = {p0, p1, p2};
  s.normals = {n0, n1, n2};
  s.triangles.push_back({0, 1, 2});
  s.triangle_material.push_back(test::add_material(s, float3(0.5f)));
  test::finish_scene(s);
  const float u = 0.2f, v = 0.3f;
  const float3 target = p0 * (1 - u - v) + p1 * u + p2 * v;
  const float3 expected = colour_of(normalize(n0 * (1 - u - v) + n1 * u + n2 * v));
  for (const test::EngineUnderTest& e : test::engines_under_test()) {
    for (float eye_y : {2.0f, -2.0f}) {
      const Camera camera = test::look_at(target + float3{0.3f, eye_y, 0.4f}, target, kTiny, kTiny);
      test::expect_film_equals(e.render(s, camera, normal_settings()).film, expected,
                               e.name + (eye_y > 0 ? ", front" : ", back"), 1e-5);
    }
    const Camera away = test::look_at({0, 2, 0}, {0, 3, 0}, kTiny, kTiny);
    test::expect_film_equals(e.render(s, away, normal_settings()).film, float3{}, e.name + ", miss", 0.0);
  }
}

// A sphere seen towards its centre: the visible point's normal points back at the camera.
TEST(NormalShading, SphereNormal) {
  Scene s;
  const float3 centre{0.5f, 1.0f, -0.5f}, eye{-1.0f, 2.0f, 1.5f};
  s.spheres.push_back({centre, 0.7f, test::add_material(s, float3(0.5f))});
  test::finish_scene(s);
  const Camera camera = test::look_at(eye, centre, kTiny, kTiny);
  for (const test::EngineUnderTest& e : test::engines_under_test())
    test::expect_film_equals(e.render(s, camera, normal_settings()).film, colour_of(normalize(eye - centre)), e.name,
                             1e-5);
}

}  // namespace
}  // namespace pt
