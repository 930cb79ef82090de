// Physics in the default mode, against closed forms that no renderer code
// computes, for every engine and every direct-light estimator (light
// sampling, uniform hemisphere, cosine hemisphere, MIS):
//  - the irradiance of a rectangular area light at points of a floor, from
//    the integral of cos over the rectangle's solid angle in closed form
//    (Lambert's formula for a parallel rectangle, by inclusion-exclusion of
//    corner rectangles), with and without an opaque square in between;
//  - the first indirect bounce: light of a large area light reflected by a
//    Lambertian floor onto the underside of a small square between them,
//    against a fine quadrature of the floor's radiance (itself from the
//    closed form, less the square's shadow, also in closed form) times the
//    form factor kernel cos cos / (pi r^2);
//  - the sky on a tilted plane: a uniform sky over the upper hemisphere gives
//    a plane tilted by theta the irradiance pi Ls (1 + cos theta) / 2.
// Statistics: the camera has a 1e-6 field of view, so every pixel sees the
// same point; 16 x 16 pixels are independent estimates (with the default
// sampler, Owen-scrambled Sobol points, each pixel scrambles its own). Per channel
// |mean - exact| < 5 SE (false failure 5.7e-7 per channel; about 3 x 4 x 3
// x 10 = 360 channel checks in this file: < 2.1e-4 in all), and SE at most
// 0.30% of exact, so that a 2% bias fails with probability 0.95: the power of
// each check, which sets its sample count (tests/support/film_checks.h).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "support/film_checks.h"
#include "support/form_factors.h"
#include "support/scene_builders.h"

// Its own namespace: its file-local names would clash with another file's of the
// program, which is compiled as one unity file (tests/CMakeLists.txt).
namespace pt::closed_form_lighting_test {
namespace {

const float3 kRho{0.4f, 0.6f, 0.8f};
const float3 kLe{2.0f, 1.0f, 0.5f};
constexpr double kPi = std::numbers::pi;

struct Estimator {
  DirectLighting direct;
  const char* name;
};
constexpr Estimator kEstimators[] = {{DirectLighting::kLightSampling, "light sampling"},
                                     {DirectLighting::kHemisphere, "hemisphere"},
                                     {DirectLighting::kCosine, "cosine"},
                                     {DirectLighting::kMis, "MIS"}};

/// Whether the estimator finds the light only by hitting it (hemisphere and
/// cosine probes): noisier where the light subtends a small solid angle.
constexpr bool hits_the_light(const Estimator& est) {
  return est.direct == DirectLighting::kHemisphere || est.direct == DirectLighting::kCosine;
}

using test::projected_solid_angle;

/// Renders the film of a camera that sees only `target`, from `eye`.
Film render_point(const test::EngineUnderTest& engine, const Scene& s, float3 eye, float3 target, RenderSettings rs) {
  return engine.render(s, test::look_at(eye, target, 1e-6f, 1e-6f), rs).film;
}

// --------------------------------------------------- area light irradiance

// The light: the rectangle [-0.6, 0.6] x [-0.4, 0.4] at height 1, facing down.
constexpr float kLx0 = -0.6f, kLx1 = 0.6f, kLz0 = -0.4f, kLz1 = 0.4f, kLh = 1.0f;

/// A large floor of albedo kRho under the light; with `occluder`, an opaque
/// black square [ox - 0.15, ox + 0.15] x [oz - 0.15, oz + 0.15] at height 0.5.
Scene floor_under_area_light(bool occluder, float ox = 0.0f, float oz = 0.0f) {
  Scene s;
  const float h = 20.0f;
  test::add_quad(s, {-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}, {0, 1, 0}, test::add_material(s, kRho));
  if (occluder)
    test::add_quad(s, {ox - 0.15f, 0.5f, oz - 0.15f}, {ox + 0.15f, 0.5f, oz - 0.15f}, {ox + 0.15f, 0.5f, oz + 0.15f},
                   {ox - 0.15f, 0.5f, oz + 0.15f}, {0, -1, 0}, test::add_material(s, float3(0.0f)));
  s.mesh_triangle_count = static_cast<uint32_t>(s.triangles.size());
  test::add_area_light(s, {0.5f * (kLx0 + kLx1), kLh, 0.5f * (kLz0 + kLz1)}, {kLx1 - kLx0, 0, 0}, {0, 0, kLz1 - kLz0},
                       {0, -1, 0}, kLe);
  test::finish_scene(s);
  return s;
}

// Catches: a wrong area-light pdf (its distance or cosine factor: the course
// renderer's is off by the distance), light counted on the wrong side, a
// missing cos at the surface or at the light, and a MIS weight that does not
// sum to one. Maximum depth 2, so that under MIS the BSDF ray competes; the
// second vertex (the light's or the occluder's black surface) reflects nothing.
TEST(ClosedFormLighting, AreaLightIrradianceOnAFloor) {
  const Scene open = floor_under_area_light(false);
  struct Point {
    float x, z;
  };
  for (Point p : {Point{0.1f, 0.05f}, Point{0.55f, -0.35f}, Point{1.3f, 0.9f}}) {
    const double psa = projected_solid_angle(kLx0, kLx1, kLz0, kLz1, kLh, p.x, p.z);
    const float3 expected = kRho * kLe * static_cast<float>(psa / kPi);
    for (const test::EngineUnderTest& e : test::engines_under_test())
      for (const Estimator& est : kEstimators) {
        // The hit-based estimators find a light of small solid angle rarely: 4x the samples.
        RenderSettings rs = test::fixed_settings(16, 16, hits_the_light(est) ? 2560 : 256);
        rs.max_depth = 2;
        rs.direct = est.direct;
        std::string what =
            e.name + ", " + est.name + ", floor point (" + std::to_string(p.x) + ", " + std::to_string(p.z) + ")";
        test::expect_film_estimates(render_point(e, open, {p.x + 0.05f, 0.3f, p.z + 0.1f}, {p.x, 0, p.z}, rs), expected,
                                    what);
      }
  }
}

// Power: the same check rejects the course renderer's area-light pdf (each
// sample weighted by its distance to the light: here 0.8-1.2 units away).
TEST(ClosedFormLighting, TheIrradianceCheckRejectsTheCoursePdf) {
  const Scene open = floor_under_area_light(false);
  const float px = 1.3f, pz = 0.9f;
  const double psa = projected_solid_angle(kLx0, kLx1, kLz0, kLz1, kLh, px, pz);
  const float3 expected = kRho * kLe * static_cast<float>(psa / kPi);
  RenderSettings rs = test::fixed_settings(16, 16, 256);
  rs.max_depth = 2;
  rs.cs184_light_pdf = true;
  Film film = render_point(test::engines_under_test()[1], open, {px + 0.05f, 0.3f, pz + 0.1f}, {px, 0, pz}, rs);
  for (int c = 0; c < 3; ++c)
    EXPECT_GT(std::fabs(test::z_score(test::film_channel_mean(film, c), expected[c])), 5.0) << "channel " << c;
}

// The occluder's shadow: from p the square at height 0.5 covers the
// rectangle twice its size at the light's height, which lies inside the light.
TEST(ClosedFormLighting, AreaLightIrradianceUnderAnOccluder) {
  const float px = 0.1f, pz = 0.05f;
  const Scene blocked = floor_under_area_light(true, px, pz);
  const double psa = projected_solid_angle(kLx0, kLx1, kLz0, kLz1, kLh, px, pz) -
                     projected_solid_angle(px - 0.3, px + 0.3, pz - 0.3, pz + 0.3, kLh, px, pz);
  const float3 expected = kRho * kLe * static_cast<float>(psa / kPi);
  for (const test::EngineUnderTest& e : test::engines_under_test())
    for (const Estimator& est : kEstimators) {
      RenderSettings rs = test::fixed_settings(16, 16, hits_the_light(est) ? 2048 : 256);
      rs.max_depth = 2;
      rs.direct = est.direct;
      test::expect_film_estimates(render_point(e, blocked, {px + 0.05f, 0.3f, pz + 0.1f}, {px, 0, pz}, rs), expected,
                                  e.name + ", " + est.name + ", under the occluder");
    }
}

// ------------------------------------------------- first indirect bounce

// A small square facing down between a lit floor and a large, low light: the
// point seen on its underside receives light that left the light, reflected
// off the floor once, and reached it. The floor fills most of the square's
// view and the light most of the floor's (less the square's shadow), so a
// cosine probe finds the floor from the square with probability 0.92 and the
// light from the floor with 0.5-0.8: the hit-based estimators converge as
// fast as light sampling.
const float3 kRhoFloor{0.7f, 0.5f, 0.3f};
const float3 kRhoSquare{0.6f, 0.6f, 0.6f};
constexpr double kFloorHalf = 1.5;                   // the floor patch [-1.5, 1.5]^2 at y = 0
constexpr double kBigLightHalf = 2.0;                // the light [-2, 2]^2 at height 1, facing down
constexpr double kSquareHalf = 0.2, kSquareY = 0.5;  // the square [-0.2, 0.2]^2 at height 0.5
constexpr double kPx = 0.07, kPz = -0.03;            // the point seen on its underside (off its diagonal)

Scene square_over_lit_floor() {
  Scene s;
  const float f = static_cast<float>(kFloorHalf), q = static_cast<float>(kSquareHalf), y = static_cast<float>(kSquareY);
  test::add_quad(s, {-f, 0, -f}, {f, 0, -f}, {f, 0, f}, {-f, 0, f}, {0, 1, 0}, test::add_material(s, kRhoFloor));
  test::add_quad(s, {-q, y, -q}, {q, y, -q}, {q, y, q}, {-q, y, q}, {0, -1, 0}, test::add_material(s, kRhoSquare));
  s.mesh_triangle_count = static_cast<uint32_t>(s.triangles.size());
  const float l = static_cast<float>(2.0 * kBigLightHalf);
  test::add_area_light(s, {0, kLh, 0}, {l, 0, 0}, {0, 0, l}, {0, -1, 0}, kLe);
  test::finish_scene(s);
  return s;
}

/// Irradiance / Le at floor point (x, z): the projected solid angle of the
/// light less that of the part the square hides. Seen from the floor point,
/// the square at height h_s covers on the light's plane (height h_l) the
/// square scaled by h_l / h_s about the point, clipped to the light.
double floor_irradiance_under_square(double x, double z) {
  const double k = kLh / kSquareY, half = kSquareHalf * k;
  const double cx = x + (0.0 - x) * k, cz = z + (0.0 - z) * k;  // the square's centre (0, 0) projected
  const double b = kBigLightHalf;
  const double x0 = std::max(cx - half, -b), x1 = std::min(cx + half, b);
  const double z0 = std::max(cz - half, -b), z1 = std::min(cz + half, b);
  const double hidden = x0 < x1 && z0 < z1 ? projected_solid_angle(x0, x1, z0, z1, kLh, x, z) : 0.0;
  return projected_solid_angle(-b, b, -b, b, kLh, x, z) - hidden;
}

/// Radiance at the point seen after exactly two bounces, per unit albedos
/// and radiance: the integral over the floor of (E(x) / pi) cos_p cos_x /
/// (pi r^2), by the midpoint rule on n x n cells.
double second_bounce_kernel(int n) {
  double sum = 0.0, cell = 2.0 * kFloorHalf / n;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < n; ++k) {
      double x = -kFloorHalf + (i + 0.5) * cell, z = -kFloorHalf + (k + 0.5) * cell;
      double dx = kPx - x, dz = kPz - z, r2 = dx * dx + kSquareY * kSquareY + dz * dz;
      double cos_both = kSquareY * kSquareY / r2;  // cos at the square times cos at the floor
      sum += floor_irradiance_under_square(x, z) / kPi * cos_both / (kPi * r2) * cell * cell;
    }
  return sum;
}

// Catches: a wrong throughput update at the bounce (albedo vs albedo / pi,
// cos / pdf of the continuation: a uniform continuation weighted as if
// cosine-distributed is 22% off here), light of the first vertex counted
// again, bounce counting off by one (--bounces only-m with m = 2 keeps exactly
// the light that reflects off the floor and then off the square), and a
// shadow ray that ignores the square (no shadow under it: +9%).
// Statistics as above; measured SE 0.24% of exact (light sampling, MIS,
// hemisphere) and 0.19% (cosine): detects a 1.6% (1.3%) bias with probability
// 0.95 at the 5-sigma bound; every check fails with the film scaled by 1.02 or
// 0.98. (A light of 1.2 x 0.8 over a patch seen by a wall, as before, left the
// hit-based estimators at 0.9% with 8x the samples: a 6% bias.)
TEST(ClosedFormLighting, FirstIndirectBounceOffALitFloor) {
  const double kernel = second_bounce_kernel(600);
  EXPECT_NEAR(kernel, second_bounce_kernel(300), 1e-5 * kernel) << "quadrature not converged";
  const float3 expected = kRhoSquare * kRhoFloor * kLe * static_cast<float>(kernel);
  const Scene s = square_over_lit_floor();
  const float3 target{static_cast<float>(kPx), static_cast<float>(kSquareY), static_cast<float>(kPz)};
  for (const test::EngineUnderTest& e : test::engines_under_test())
    for (const Estimator& est : kEstimators) {
      // Light sampling and MIS sample a light this close with a pdf that varies
      // more than the hit-based probes' weights: 4x the samples.
      RenderSettings rs = test::fixed_settings(16, 16, hits_the_light(est) ? 256 : 1024);
      rs.max_depth = 2;
      rs.bounces = BounceMode::kOnlyBounceM;
      rs.direct = est.direct;
      test::expect_film_estimates(render_point(e, s, target + float3{0.1f, -0.3f, 0.05f}, target, rs), expected,
                                  e.name + ", " + est.name + ", second bounce");
    }
}

// ---------------------------------------------------- sky on a tilted plane

// Catches: the sky sampled over the wrong hemisphere or with the wrong pdf,
// sky light below the horizon, and a cosine or visibility bound by the
// geometric normal where the shading normal is meant (or the reverse).
TEST(ClosedFormLighting, SkyOnATiltedPlane) {
  const float3 ls{0.8f, 1.0f, 1.2f};
  for (double theta_deg : {0.0, 50.0, 120.0}) {
    const double theta = theta_deg * kPi / 180.0;
    const float3 n{static_cast<float>(std::sin(theta)), static_cast<float>(std::cos(theta)), 0.0f};
    const float3 u{n.y, -n.x, 0.0f}, w{0, 0, 1};  // the plane's edges
    Scene s;
    test::add_quad(s, u * -20.0f + w * -20.0f, u * 20.0f + w * -20.0f, u * 20.0f + w * 20.0f, u * -20.0f + w * 20.0f, n,
                   test::add_material(s, kRho));
    s.sky = SkyLight{ls};
    test::finish_scene(s);
    const float3 expected = kRho * ls * static_cast<float>((1.0 + std::cos(theta)) / 2.0);
    for (const test::EngineUnderTest& e : test::engines_under_test())
      for (const Estimator& est : kEstimators) {
        RenderSettings rs = test::fixed_settings(16, 16, 192);
        rs.max_depth = 2;
        rs.direct = est.direct;
        // A point off the quad's diagonal: a camera this narrow aimed at the
        // edge two triangles share would send many rays through the crack that
        // Moller-Trumbore leaves between them.
        const float3 p = u * 0.3f + w * 0.1f;
        test::expect_film_estimates(render_point(e, s, p + n * 0.5f + u * 0.1f, p, rs), expected,
                                    e.name + ", " + est.name + ", plane tilted by " + std::to_string(theta_deg));
      }
  }
}

}  // namespace
}  // namespace pt::closed_form_lighting_test
