// A point p of a Lambertian floor (albedo rho) under a parallel emissive
// rectangle (radiance Le, not an area light, black albedo) has radiance
// rho Le / pi * integral of cos over the rectangle's solid angle, the form
// factor, which has a closed form. Light sampling finds the rectangle only with
// the cosine-weighted bounce ray (so this tests the bounce's distribution and
// weight, which furnaces cannot see); hemisphere sampling finds it with its
// uniform rays. Both at maximum depth 2 (nothing else reaches p: floor -> floor
// is impossible and the emitter reflects nothing).
//
// Statistics: a camera with a 1e-6 field of view sees only p; 16 x 16 pixels x
// 512 samples are independent estimates; per channel |mean - exact| < 5 SE
// (false failure 5.7e-7 per comparison, 2 points x 2 estimators x 3 channels
// = 12 per engine: < 7e-6) and SE at most 0.30% of exact (measured 0.20%),
// so that a 2% bias fails with probability 0.95 (tests/support/film_checks.h). About 0.3 s per engine.
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "support/film_checks.h"
#include "support/form_factors.h"
#include "kernels/math/sampling.h"
#include "support/scene_builders.h"

// Its own namespace: its file-local names would clash with another file's of the
// program, which is compiled as one unity file (tests/CMakeLists.txt).
namespace pt::emitter_form_factor_test {
namespace {

const float3 kRho{0.4f, 0.6f, 0.8f};
const float3 kLe{2.0f, 1.0f, 0.5f};
constexpr double kHeight = 0.5;
constexpr float kX0 = -1.0f, kX1 = 1.0f, kZ0 = -0.8f, kZ1 = 1.2f;  // the rectangle at y = kHeight

/// Integral of cos over the rectangle seen from floor point (px, 0, pz), by inclusion-exclusion.
double projected_solid_angle(double px, double pz) {
  return test::projected_solid_angle(kX0, kX1, kZ0, kZ1, kHeight, px, pz);
}

Scene floor_under_emitter() {
  Scene s;
  const float h = 20.0f, y = static_cast<float>(kHeight);
  test::add_quad(s, {-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}, {0, 1, 0}, test::add_material(s, kRho));
  test::add_quad(s, {kX0, y, kZ0}, {kX1, y, kZ0}, {kX1, y, kZ1}, {kX0, y, kZ1}, {0, -1, 0},
                 test::add_material(s, float3{}, kLe));
  test::finish_scene(s);
  return s;
}

// Catches: a bounce drawn uniformly but weighted as if cosine-distributed (or
// the reverse), a missing cos in the hemisphere estimator, emission of a
// two-sided emitter lost on its back... and the closed form itself is checked
// by two estimators that share nothing but the scene.
TEST(EmitterFormFactor, FloorUnderAnEmissiveRectangle) {
  const Scene s = floor_under_emitter();
  struct Point {
    float x, z;
  };
  for (Point p : {Point{0.1f, 0.3f}, Point{1.4f, -0.6f}}) {
    const Camera camera = test::look_at({p.x + 0.05f, 0.3f, p.z + 0.1f}, {p.x, 0.0f, p.z}, 1e-6f, 1e-6f);
    const float3 expected = kRho * kLe * static_cast<float>(projected_solid_angle(p.x, p.z) / std::numbers::pi);
    for (const test::EngineUnderTest& e : test::engines_under_test())
      for (DirectLighting direct : {DirectLighting::kLightSampling, DirectLighting::kHemisphere}) {
        RenderSettings rs = test::fixed_settings(16, 16, 512);
        rs.max_depth = 2;
        rs.direct = direct;
        std::string what = e.name + (direct == DirectLighting::kHemisphere ? ", hemisphere" : ", light sampling");
        what += ", point (" + std::to_string(p.x) + ", " + std::to_string(p.z) + ")";
        test::expect_film_estimates(e.render(s, camera, rs).film, expected, what);
      }
  }
}

}  // namespace
}  // namespace pt::emitter_form_factor_test
