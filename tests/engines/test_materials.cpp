// The second part of the assignment against what holds exactly, for every
// engine:
//  - a mirror sphere of reflectance 1 and a smooth glass sphere with
//    reflectance = transmittance = 1 inside a uniform environment are
//    invisible: every path returns the environment's radiance times a
//    throughput of exactly 1 (reflection) or 1/eta^2 * eta^2 (through the
//    glass), so every pixel equals the environment within float rounding
//    (1e-5 relative), in the physical and the course's definitions;
//  - a constant environment map over the upper hemisphere (black below) is
//    the uniform sky it replaces: the images agree within noise;
//  - a thin lens of radius 0 is the pinhole (the same rays); every ray of a
//    thin lens passes through the pinhole ray's point on the focal plane, so
//    a plane at the focal distance renders as the pinhole renders it, and
//    one away from it does not (the power of that check);
//  - stability where methods fail: caustics through a glass sphere lit only
//    by a small light stay finite and agree with a 16x longer render; the
//    smallest and largest microfacet roughness and an index of refraction
//    near 1 produce no NaN or infinity.
#include <cmath>
#include <cstdio>
#include <memory>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "kernels/scene/camera.h"
#include "kernels/scene/environment_map.h"
#include "support/scene_builders.h"
#include "support/statistics.h"

namespace pt {
namespace {

const float3 kEnv{0.7f, 1.1f, 1.6f};

uint32_t add_kind(Scene& s, MaterialKind kind, float3 albedo, float3 transmittance = float3(0.0f), float ior = 1.5f) {
  uint32_t m = test::add_material(s, albedo);
  s.materials[m].kind = kind;
  s.materials[m].transmittance = transmittance;
  s.materials[m].ior = ior;
  return m;
}

std::shared_ptr<const EnvironmentMap> constant_map(float3 radiance, int width, int height, bool upper_half_only) {
  std::vector<float3> texels(size_t(width) * height, radiance);
  if (upper_half_only)
    for (size_t i = size_t(width) * (height / 2); i < texels.size(); ++i) texels[i] = float3(0.0f);
  return std::make_shared<EnvironmentMap>(width, height, std::move(texels));
}

struct Mode {
  const char* name;
  DirectLighting direct;
  bool course;
};
const Mode kModes[] = {{"light sampling", DirectLighting::kLightSampling, false},
                       {"MIS", DirectLighting::kMis, false},
                       {"hemisphere", DirectLighting::kHemisphere, false},
                       {"light sampling, course definitions", DirectLighting::kLightSampling, true}};

TEST(Materials, MirrorAndGlassSpheresAreInvisibleInAUniformEnvironment) {
  for (MaterialKind kind : {MaterialKind::kMirror, MaterialKind::kGlass}) {
    Scene s;
    uint32_t m = add_kind(s, kind, float3(1.0f), float3(1.0f), 1.45f);
    s.spheres.push_back({{0.0f, 0.0f, 0.0f}, 1.0f, m});
    test::finish_scene(s);
    set_environment(s, constant_map(kEnv, 16, 8, false));
    Camera cam = test::look_at({0.3f, 0.2f, 4.0f}, {0.0f, 0.0f, 0.0f}, 0.35f, 0.3f);
    for (const Mode& mode : kModes) {
      RenderSettings rs = test::fixed_settings(24, 20, 4);
      rs.max_depth = 64;      // a path stays inside the glass for more bounces with probability < 1e-80
      rs.rr_continue = 1.0f;  // no roulette: every path's weight is exact
      rs.direct = mode.direct;
      rs.cs184_materials = mode.course;
      for (const test::EngineUnderTest& engine : test::engines_under_test()) {
        RenderOutput out = engine.render(s, cam, rs);
        double worst = 0.0;
        for (const float3& px : out.film.radiance)
          for (int c = 0; c < 3; ++c) worst = std::max(worst, std::fabs(double(px[c]) / kEnv[c] - 1.0));
        EXPECT_LT(worst, 1e-5) << engine.name << ", " << (kind == MaterialKind::kMirror ? "mirror" : "glass") << ", "
                               << mode.name;
      }
    }
  }
}

// A mirror floor under a large area light, seen from below the light: with
// -m 1 every pixel shows the light after one reflection, R x Le exactly (the
// mirror at the last vertex still sends its ray, since it takes no light
// sample); with -m 0 only what the camera sees directly counts: black.
TEST(Materials, AMirrorAtTheLastVertexShowsTheLightItReflects) {
  const float3 reflectance{0.9f, 0.6f, 0.3f}, le{2.0f, 3.0f, 4.0f};
  Scene s;
  uint32_t mirror = add_kind(s, MaterialKind::kMirror, reflectance);
  test::add_parallelogram(s, {-20.0f, 0.0f, 20.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -40.0f}, mirror);
  test::add_area_light(s, {0.0f, 2.0f, 0.0f}, {40.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 40.0f}, {0.0f, -1.0f, 0.0f}, le);
  test::finish_scene(s);
  Camera cam = test::look_at({0.0f, 1.0f, 0.5f}, {0.0f, 0.0f, -0.5f}, 0.3f, 0.3f);
  for (const Mode& mode : kModes)
    for (int depth : {0, 1, 2}) {
      RenderSettings rs = test::fixed_settings(12, 12, 2);
      rs.max_depth = depth;
      rs.direct = mode.direct;
      const float3 expected = depth == 0 ? float3(0.0f) : reflectance * le;
      for (const test::EngineUnderTest& engine : test::engines_under_test()) {
        Film f = engine.render(s, cam, rs).film;
        for (const float3& px : f.radiance)
          for (int c = 0; c < 3; ++c)
            ASSERT_NEAR(px[c], expected[c], 1e-5f * expected[c])
                << engine.name << ", " << mode.name << ", -m " << depth;
      }
    }
}

/// A diffuse floor and sphere under the sky (or a map standing in for it).
Scene sky_scene() {
  Scene s;
  uint32_t grey = test::add_material(s, {0.6f, 0.5f, 0.4f});
  test::add_parallelogram(s, {-3.0f, 0.0f, 3.0f}, {6.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -6.0f}, grey);
  s.spheres.push_back({{0.0f, 0.6f, 0.0f}, 0.6f, grey});
  test::finish_scene(s);
  return s;
}

TEST(EnvironmentLight, AConstantMapOverTheUpperHemisphereIsTheSky) {
  // The map's lower half is black; its rows are split at the horizon, where
  // the bilinear lookup blends over half a texel (0.18 degrees at 512 rows):
  // a change of the floor's irradiance below 1e-5 relative. Power of the
  // Stouffer bound (tests/support/statistics.h): detects a 1.7% (light
  // sampling) and 0.8% (MIS) bias of the lit pixels with probability 0.95.
  Scene sky = sky_scene();
  sky.sky = SkyLight{kEnv};
  Scene env = sky_scene();
  set_environment(env, constant_map(kEnv, 1024, 512, true));
  Camera cam = test::look_at({0.0f, 1.5f, 3.5f}, {0.0f, 0.4f, 0.0f}, 0.6f, 0.45f);
  for (DirectLighting direct : {DirectLighting::kLightSampling, DirectLighting::kMis}) {
    RenderSettings rs = test::fixed_settings(24, 18, 512);
    rs.max_depth = 3;
    rs.direct = direct;
    const test::EngineUnderTest& engine = test::engines_under_test().back();
    Film a = engine.render(sky, cam, rs).film;
    rs.seed = 2;
    Film b = engine.render(env, cam, rs).film;
    test::expect_same_image_within_noise(a, b, engine.name + ": sky vs constant map");
  }
}

TEST(ThinLens, RadiusZeroIsThePinhole) {
  Camera c = test::look_at({0.2f, 1.0f, 3.0f}, {0.0f, 0.5f, 0.0f}, 0.5f, 0.4f);
  c.focal_distance = 2.7f;
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 1000; ++i) {
    float sx = u(rng), sy = u(rng);
    Vec3T<float> org, dir;
    thin_lens_ray(c, sx, sy, u(rng), u(rng), org, dir);
    Vec3T<float> pin = camera_ray_direction(c, sx, sy);
    EXPECT_EQ(to_float3(org), c.position);
    EXPECT_LT(length(to_float3(dir) - to_float3(pin)), 1e-6f);
  }
}

TEST(ThinLens, EveryLensRayMeetsThePinholeRayOnTheFocalPlane) {
  Camera c = test::look_at({0.2f, 1.0f, 3.0f}, {0.0f, 0.5f, 0.0f}, 0.5f, 0.4f);
  c.lens_radius = 0.25f;
  c.focal_distance = 2.7f;
  std::mt19937 rng(6);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  for (int i = 0; i < 1000; ++i) {
    float sx = u(rng), sy = u(rng);
    Vec3T<float> org, dir;
    thin_lens_ray(c, sx, sy, u(rng), u(rng), org, dir);
    float3 pin = to_float3(camera_ray_direction(c, sx, sy));
    float3 focus = c.position + pin * (c.focal_distance / dot(pin, -c.to_camera));
    float3 o = to_float3(org), d = to_float3(dir);
    float t = dot(focus - o, d);
    EXPECT_LT(length(o + d * t - focus), 2e-6f * c.focal_distance) << i;
    EXPECT_LE(length(o - c.position), c.lens_radius * (1.0f + 1e-6f));
    EXPECT_NEAR(length(d), 1.0f, 1e-6f);
  }
}

/// Emitting stripes on the plane z = 0, facing +z, over a black backdrop.
Scene stripes() {
  Scene s;
  uint32_t light = test::add_material(s, float3(0.0f), {3.0f, 2.0f, 1.0f});
  uint32_t black = test::add_material(s, float3(0.0f));
  test::add_parallelogram(s, {-2.0f, -2.0f, -0.01f}, {4.0f, 0.0f, 0.0f}, {0.0f, 4.0f, 0.0f}, black);
  for (int i = -4; i < 4; ++i)
    test::add_parallelogram(s, {0.2f * i, -1.0f, 0.0f}, {0.1f, 0.0f, 0.0f}, {0.0f, 2.0f, 0.0f}, light);
  test::finish_scene(s);
  return s;
}

/// Largest per-pixel |Y_a - Y_b| / sqrt(var_a + var_b) (the power of the
/// in-focus check: a defocused image must fail it by far).
double largest_pixel_z(const Film& a, const Film& b) {
  double worst = 0.0;
  for (size_t i = 0; i < a.radiance.size(); ++i) {
    double d = double(illuminance(a.radiance[i])) - illuminance(b.radiance[i]);
    double v = double(a.variance[i]) + b.variance[i];
    if (v > 0.0) worst = std::max(worst, std::fabs(d) / std::sqrt(v));
  }
  return worst;
}

// In focus: the lens image and the pinhole's agree within noise (Stouffer
// bound: detects a 1.6% bias with probability 0.95); out of focus, some pixel
// differs by more than 10 sigma.
TEST(ThinLens, APlaneAtTheFocalDistanceIsSharpAndOneAwayFromItIsNot) {
  Scene s = stripes();
  Camera pinhole = test::look_at({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, 0.3f, 0.3f);
  RenderSettings rs = test::fixed_settings(32, 32, 512);
  rs.max_depth = 0;  // emission only: the image is the plane seen through the lens
  for (const test::EngineUnderTest& engine : test::engines_under_test()) {
    Film sharp = engine.render(s, pinhole, rs).film;
    Camera lens = pinhole;
    lens.lens_radius = 0.2f;
    lens.focal_distance = 3.0f;
    RenderSettings rs2 = rs;
    rs2.seed = 9;
    test::expect_same_image_within_noise(sharp, engine.render(s, lens, rs2).film, engine.name + ": in focus");
    lens.focal_distance = 1.5f;
    EXPECT_GT(largest_pixel_z(sharp, engine.render(s, lens, rs2).film), 10.0) << engine.name << ": out of focus";
  }
}

/// A glass ball above a diffuse floor, lit only by a small area light.
Scene caustic_scene(float ior) {
  Scene s;
  uint32_t floor = test::add_material(s, float3(0.7f));
  test::add_parallelogram(s, {-2.0f, 0.0f, 2.0f}, {4.0f, 0.0f, 0.0f}, {0.0f, 0.0f, -4.0f}, floor);
  uint32_t glass = add_kind(s, MaterialKind::kGlass, float3(1.0f), float3(1.0f), ior);
  s.spheres.push_back({{0.0f, 0.8f, 0.0f}, 0.5f, glass});
  test::add_area_light(s, {0.0f, 2.5f, 0.0f}, {0.25f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.25f}, {0.0f, -1.0f, 0.0f},
                       float3(60.0f));
  test::finish_scene(s);
  return s;
}

void expect_finite(const RenderOutput& out, const std::string& what) {
  EXPECT_EQ(out.stats.invalid_samples, 0u) << what;
  for (const float3& px : out.film.radiance)
    ASSERT_TRUE(std::isfinite(px.x) && std::isfinite(px.y) && std::isfinite(px.z)) << what;
}

TEST(Stability, CausticsThroughGlassStayFiniteAndUnbiased) {
  Scene s = caustic_scene(1.5f);
  Camera cam = test::look_at({0.0f, 2.0f, 3.0f}, {0.0f, 0.3f, 0.0f}, 0.5f, 0.5f);
  RenderSettings rs = test::fixed_settings(24, 24, 1024);
  rs.max_depth = 6;
  const test::EngineUnderTest& reference = test::engines_under_test()[0];
  RenderOutput long_run = reference.render(s, cam, rs);
  expect_finite(long_run, "reference, 1024 spp");
  rs.samples_per_pixel = 64;
  rs.seed = 3;
  for (const test::EngineUnderTest& engine : test::engines_under_test()) {
    RenderOutput out = engine.render(s, cam, rs);
    expect_finite(out, engine.name);
    // The image means, whose error is the pixels' combined (heavy-tailed but
    // finite-variance) noise: |z| < 4.42 (two-sided 1e-5). A guard against
    // gross bias only: the 64-sample caustic's image mean is known to 8%, so
    // this detects a 51% bias with probability 0.95 (a 2% one would take
    // about 650x the samples).
    double z = test::mean_difference_z(out.film, long_run.film);
    EXPECT_LT(std::fabs(z), test::kZ1e5) << engine.name << ": caustic image mean z = " << z;
    const test::ImageMean a = test::image_mean(out.film), b = test::image_mean(long_run.film);
    std::printf("  %s: caustic image mean z %.2f, detects a %.2g%% bias with probability 0.95\n", engine.name.c_str(),
                z, 100.0 * (test::kZ1e5 + test::kZ95) * std::hypot(a.standard_error, b.standard_error) / b.mean);
  }
}

TEST(Stability, ExtremeRoughnessAndIndicesGiveNoNaNOrInfinity) {
  for (float alpha : {kMinMicrofacetAlpha, 0.001f, 10.0f}) {
    for (float ior : {1.0001f, 1.45f, 4.0f}) {
      Scene s = caustic_scene(ior);
      uint32_t metal = add_kind(s, MaterialKind::kMicrofacet, float3(0.0f));
      s.materials[metal].alpha = alpha;
      s.materials[metal].eta = {0.2f, 0.9f, 1.1f};
      s.materials[metal].k = {3.9f, 2.4f, 2.2f};
      s.spheres.push_back({{0.9f, 0.4f, 0.3f}, 0.4f, metal});
      s.sky = SkyLight{float3(0.3f)};
      test::finish_scene(s);
      Camera cam = test::look_at({0.5f, 1.5f, 3.0f}, {0.4f, 0.4f, 0.0f}, 0.4f, 0.4f);
      for (DirectLighting direct :
           {DirectLighting::kLightSampling, DirectLighting::kMis, DirectLighting::kHemisphere}) {
        RenderSettings rs = test::fixed_settings(16, 16, 16);
        rs.max_depth = 8;
        rs.direct = direct;
        for (const test::EngineUnderTest& engine : test::engines_under_test())
          expect_finite(engine.render(s, cam, rs),
                        engine.name + " alpha " + std::to_string(alpha) + " ior " + std::to_string(ior));
      }
    }
  }
}

}  // namespace
}  // namespace pt
