// Direct light from delta lights has no noise: a Lambertian surface of albedo
// A under a directional or point light of colour E (CS184 semantics: incident
// radiance E, pdf 1, no falloff) has radiance A / pi * E * cos(theta) exactly,
// so these tests assert to float precision (1e-6 or 1e-5 relative: any bias
// above that fails, always; no statistics), for every engine. Point-light
// cases use a camera with a field of view of 1e-6, so that every sample of a
// pixel sees the same point (cos varies by < 1e-6 over the footprint). Also
// exact zeros: shadowed points, the unlit side of a surface, and hemisphere
// sampling (which cannot find delta lights).
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "support/film_checks.h"
#include "kernels/math/sampling.h"
#include "support/scene_builders.h"

namespace pt {
namespace {

const float3 kAlbedo{0.2f, 0.5f, 0.8f};
const float3 kLightColour{3.0f, 2.0f, 1.0f};
constexpr float kTiny = 1e-6f;

/// A 20 x 20 plane at y = 0 with shading normal +Y and albedo kAlbedo.
Scene lit_plane() {
  Scene s;
  const float h = 10.0f;
  test::add_quad(s, {-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}, {0, 1, 0}, test::add_material(s, kAlbedo));
  return s;
}

float3 lambert(float cosine) { return kAlbedo * kLightColour * (kInvPi * cosine); }

RenderSettings settings(int max_depth) {
  RenderSettings rs = test::fixed_settings(8, 8, 4);
  rs.max_depth = max_depth;
  return rs;
}

// Every pixel of a wide view of the plane. Catches a missing 1/pi, a cos taken
// against the geometric instead of the light's direction, a falloff, light
// added again at deeper bounces (m = 3: bounce rays escape into nothing).
TEST(DirectLightClosedForm, DirectionalLightOnAPlane) {
  Scene s = lit_plane();
  const float3 to_light = normalize(float3{1.0f, 2.0f, 0.5f});
  s.directional_lights.push_back({to_light, kLightColour});
  test::finish_scene(s);
  const Camera camera = test::look_at({0.3f, 2.0f, 0.1f}, {0, 0, 0}, 0.3f, 0.3f);
  for (const test::EngineUnderTest& e : test::engines_under_test())
    for (int m : {1, 3})
      test::expect_film_equals(e.render(s, camera, settings(m)).film, lambert(to_light.y),
                               e.name + ", m=" + std::to_string(m));
}

// Three light positions over one point p of the plane, including straight
// above it (cos 1), at unchanged colour whatever the distance.
TEST(DirectLightClosedForm, PointLightWithoutFalloff) {
  const float3 p{0.2f, 0.0f, 0.3f};
  const Camera camera = test::look_at({0.7f, 1.5f, -0.4f}, p, kTiny, kTiny);
  for (float3 light :
       {float3{0.2f, 3.0f, 0.3f}, float3{0.0f, 1.0f, 0.0f}, float3{2.0f, 0.5f, -1.0f}, float3{-40.0f, 30.0f, 25.0f}}) {
    Scene s = lit_plane();
    s.point_lights.push_back({light, kLightColour});
    test::finish_scene(s);
    const float cosine = normalize(light - p).y;
    for (const test::EngineUnderTest& e : test::engines_under_test())
      test::expect_film_equals(e.render(s, camera, settings(1)).film, lambert(cosine),
                               e.name + ", light at y " + std::to_string(light.y), 1e-5);
  }
}

// Lights add: a point light and a directional light together give the sum.
// On a sphere, so the normal comes from the sphere: the camera looks at the
// centre, so it sees the point whose normal points back at the camera.
TEST(DirectLightClosedForm, TwoLightsOnASphereAdd) {
  Scene s;
  const float3 centre{0.0f, 1.0f, 0.0f}, eye{1.0f, 2.5f, 2.0f};
  s.spheres.push_back({centre, 0.5f, test::add_material(s, kAlbedo)});
  const float3 to_sun = normalize(float3{-0.5f, 1.0f, 1.0f}), bulb{2.0f, 1.5f, 0.5f};
  s.directional_lights.push_back({to_sun, kLightColour});
  s.point_lights.push_back({bulb, kLightColour * 0.5f});
  test::finish_scene(s);
  const float3 n = normalize(eye - centre), p = centre + n * 0.5f;
  const float3 expected = lambert(dot(n, to_sun)) + lambert(dot(n, normalize(bulb - p))) * 0.5f;
  const Camera camera = test::look_at(eye, centre, kTiny, kTiny);
  for (const test::EngineUnderTest& e : test::engines_under_test())
    test::expect_film_equals(e.render(s, camera, settings(1)).film, expected, e.name, 1e-5);
}

// A quad whose stored shading normal n_s is tilted away from its geometric
// normal: the cosine uses the shading normal, turned to the side the ray
// arrives on (-n_s seen from below), while the geometric normal decides which
// side is lit. Catches a shading normal left unflipped on the back side (the
// renderer then falls back to the geometric normal) and a cosine taken
// against the geometric normal.
TEST(DirectLightClosedForm, ShadingNormalOnBothSides) {
  const float3 n_s = normalize(float3{0.3f, 1.0f, -0.2f});
  const float3 p{0.2f, 0.0f, 0.3f};
  struct Side {
    const char* name;
    float3 to_light, eye, normal;
  };
  const Side sides[] = {{"front", normalize(float3{-0.4f, 1.0f, 0.2f}), {0.7f, 1.5f, -0.4f}, n_s},
                        {"back", normalize(float3{0.1f, -1.0f, 0.5f}), {0.7f, -1.5f, -0.4f}, -n_s}};
  for (const Side& side : sides) {
    Scene s;
    const float h = 10.0f;
    test::add_quad(s, {-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}, n_s, test::add_material(s, kAlbedo));
    s.directional_lights.push_back({side.to_light, kLightColour});
    test::finish_scene(s);
    const Camera camera = test::look_at(side.eye, p, kTiny, kTiny);
    for (const test::EngineUnderTest& e : test::engines_under_test())
      test::expect_film_equals(e.render(s, camera, settings(1)).film, lambert(dot(side.normal, side.to_light)),
                               e.name + ", " + side.name, 1e-5);
  }
}

// Exact zeros: a small occluder between p and the light; the underside of the
// plane (lit from above, seen from below: both sides reflect, but light must
// arrive on the side the camera sees); hemisphere sampling, which can never
// hit a delta light.
TEST(DirectLightClosedForm, ShadowsUnlitSidesAndHemisphereSamplingAreBlack) {
  const float3 p{0.2f, 0.0f, 0.3f};
  Scene s = lit_plane();
  s.point_lights.push_back({{0.2f, 3.0f, 0.3f}, kLightColour});
  s.directional_lights.push_back({normalize(float3{0.1f, 1.0f, 0.0f}), kLightColour});
  Scene shadowed = s;
  const float w = 0.3f;
  test::add_quad(shadowed, {0.2f - w, 1.5f, 0.3f - w}, {0.2f + w, 1.5f, 0.3f - w}, {0.2f + w, 1.5f, 0.3f + w},
                 {0.2f - w, 1.5f, 0.3f + w}, {0, 1, 0}, test::add_material(shadowed, float3(0.5f)));
  test::finish_scene(s);
  test::finish_scene(shadowed);
  const Camera above = test::look_at({0.7f, 1.0f, -0.4f}, p, kTiny, kTiny);
  const Camera below = test::look_at({0.7f, -1.5f, -0.4f}, p, kTiny, kTiny);
  for (const test::EngineUnderTest& e : test::engines_under_test()) {
    test::expect_film_equals(e.render(shadowed, above, settings(1)).film, float3{}, e.name + ", shadowed", 0.0);
    test::expect_film_equals(e.render(s, below, settings(3)).film, float3{}, e.name + ", underside", 0.0);
    RenderSettings rs = settings(1);
    rs.direct = DirectLighting::kHemisphere;
    test::expect_film_equals(e.render(s, above, rs).film, float3{}, e.name + ", hemisphere sampling", 0.0);
  }
}

}  // namespace
}  // namespace pt
