// The live view's camera navigation: orbit, pan and zoom keep the course's
// camera model consistent (distance to the target, an orthonormal basis that
// looks at it), moves undo exactly, a pan carries the point under the mouse
// with it to the pixel, and the camera file a view saves resolves to the very
// camera the view renders.
#include <cmath>
#include <cstring>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "io/camera_setup.h"
#include "live/camera_nav.h"
#include "support/run_process.h"
#include "support/test_support.h"

namespace pt::live {
namespace {

constexpr int kW = 320, kH = 240;

const Scene& cornell() {
  static const LoadResult loaded = load_collada_file(test::project_scene("cornell_spheres.dae"));
  return loaded.scene;
}

ViewCamera start_view() {
  const Scene& s = cornell();
  return view_from_camera(resolve_camera(s, kW, kH), kW, kH, s.bounds.center(), nav_limits(s.bounds));
}

float3 column(const ViewCamera& v, int j) { return {v.c2w[0][j], v.c2w[1][j], v.c2w[2][j]}; }

/// |pos - target| = r, an orthonormal right-handed basis, and to_camera pointing from the target to the camera.
void expect_consistent(const ViewCamera& v) {
  const float3 x = column(v, 0), y = column(v, 1), z = column(v, 2);
  EXPECT_NEAR(length(v.position - v.target), v.r, 1e-5f * v.r);
  EXPECT_NEAR(length(x), 1.0f, 1e-6f);
  EXPECT_NEAR(length(y), 1.0f, 1e-6f);
  EXPECT_NEAR(length(z), 1.0f, 1e-6f);
  EXPECT_NEAR(dot(x, y), 0.0f, 1e-6f);
  EXPECT_NEAR(dot(y, z), 0.0f, 1e-6f);
  EXPECT_NEAR(dot(x, z), 0.0f, 1e-6f);
  EXPECT_NEAR(length(cross(x, y) - z), 0.0f, 1e-6f);
  EXPECT_NEAR(length(normalize(v.position - v.target) - z), 0.0f, 1e-5f);
  EXPECT_GT(v.phi, 0.0f);
  EXPECT_LT(v.phi, float(std::numbers::pi));
  EXPECT_EQ(camera_settings_problem(v), "");
}

/// Every field of two resolved cameras, bit for bit.
void expect_same_camera(const Camera& a, const Camera& b) { EXPECT_EQ(std::memcmp(&a, &b, sizeof(Camera)), 0); }

/// Whether two floats are equal or adjacent.
bool within_one_float(float a, float b) { return a == b || std::nextafter(a, b) == b; }

TEST(CameraNav, TheSceneCameraOrbitsTheSceneCentre) {
  const Scene& s = cornell();
  const ViewCamera v = start_view();
  EXPECT_NEAR(length(v.target - s.bounds.center()), 0.0f, 1e-5f * length(s.bounds.extent()));
  EXPECT_NEAR(v.r, length(v.position - v.target), 1e-5f * v.r);
}

// The unmoved view is the command line's camera: position and basis to the
// bit; the tangents of the half fields of view to the bit where the file's
// degrees (floats) can carry them, else to the adjacent float (the view then
// differs from `pathtracer -s N` without -c in a few pixels, and equals
// `pathtracer -c` of its saved file as every view does).
TEST(CameraNav, TheUnmovedViewIsTheCommandLinesCamera) {
  std::vector<std::filesystem::path> scenes = {test::project_scene("cornell_spheres.dae"),
                                               test::project_scene("cornell_materials.dae")};
  if (test::shared_scenes_available())
    for (const std::string& name : test::shared_scene_names()) scenes.push_back(test::shared_scene(name));
  int cases = 0, exact = 0;
  for (const auto& path : scenes) {
    LoadResult loaded = load_collada_file(path);
    const Scene& s = loaded.scene;
    for (auto [w, h] : {std::pair{320, 240}, std::pair{480, 360}, std::pair{800, 600}, std::pair{160, 120},
                        std::pair{200, 300}, std::pair{1024, 576}})
      for (bool framing : {false, true}) {
        SCOPED_TRACE(path.filename().string() + " " + std::to_string(w) + "x" + std::to_string(h));
        const Camera want = resolve_camera(s, w, h, framing);
        const Camera got = resolve_camera(view_from_camera(want, w, h, s.bounds.center(), nav_limits(s.bounds)), w, h);
        EXPECT_EQ(got.position, want.position);
        EXPECT_EQ(got.screen_x, want.screen_x);
        EXPECT_EQ(got.screen_y, want.screen_y);
        EXPECT_EQ(got.to_camera, want.to_camera);
        EXPECT_TRUE(within_one_float(got.tan_half_hfov, want.tan_half_hfov));
        EXPECT_TRUE(within_one_float(got.tan_half_vfov, want.tan_half_vfov));
        ++cases;
        exact += got.tan_half_hfov == want.tan_half_hfov && got.tan_half_vfov == want.tan_half_vfov;
      }
  }
  std::printf("    the unmoved view is the command line's camera to the bit in %d of %d scenes x sizes x framings\n",
              exact, cases);
}

TEST(CameraNav, OrbitKeepsTheDistanceAndABasisThatLooksAtTheTarget) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> px(-400.0, 400.0);
  ViewCamera v = start_view();
  for (int i = 0; i < 200; ++i) {
    v = orbit(v, px(rng), px(rng), kW, kH);
    expect_consistent(v);
    if (HasFailure()) return;
  }
}

TEST(CameraNav, AnOrbitAndItsOppositeReturnToTheStart) {
  const ViewCamera a = orbit(start_view(), 10.0, 5.0, kW, kH);  // on the +Y basis from here on
  const ViewCamera b = orbit(orbit(a, 73.25, -41.5, kW, kH), -73.25, 41.5, kW, kH);
  EXPECT_NEAR(b.phi, a.phi, 1e-6f);
  EXPECT_NEAR(b.theta, a.theta, 1e-6f);
  EXPECT_NEAR(length(b.position - a.position), 0.0f, 1e-5f * a.r);
}

TEST(CameraNav, DraggingAcrossTheViewTurnsHalfWayRound) {
  const ViewCamera a = orbit(start_view(), 1.0, 0.0, kW, kH);
  const ViewCamera b = orbit(a, kW, 0.0, kW, kH);  // theta - pi
  const float3 da = a.position - a.target, db = b.position - b.target;
  EXPECT_NEAR(db.x, -da.x, 1e-5f * a.r);
  EXPECT_NEAR(db.y, da.y, 1e-5f * a.r);
  EXPECT_NEAR(db.z, -da.z, 1e-5f * a.r);
}

TEST(CameraNav, TiltStopsShortOfThePoles) {
  const ViewCamera top = orbit(start_view(), 0.0, 1e5, kW, kH);
  const ViewCamera bottom = orbit(start_view(), 0.0, -1e5, kW, kH);
  EXPECT_FLOAT_EQ(top.phi, 1e-4f);
  EXPECT_FLOAT_EQ(bottom.phi, float(std::numbers::pi - 1e-4));
  expect_consistent(top);
  expect_consistent(bottom);
}

TEST(CameraNav, PanCarriesThePointAtTheTargetsDepthWithTheMouse) {
  const ViewCamera a = orbit(start_view(), 30.0, 20.0, kW, kH);
  const Camera before = resolve_camera(a, kW, kH);
  for (auto [dx, dy] : {std::pair{25.0, -10.0}, std::pair{-3.5, 40.25}, std::pair{160.0, 0.0}}) {
    const ViewCamera b = pan(a, dx, dy, before.tan_half_vfov, kH, nav_limits(cornell().bounds));
    const Camera after = resolve_camera(b, kW, kH);
    float px = 0, py = 0;
    ASSERT_TRUE(project_to_pixel(after, kW, kH, a.target, px, py));
    EXPECT_NEAR(px, kW / 2.0 + dx, 2e-3);
    EXPECT_NEAR(py, kH / 2.0 + dy, 2e-3);
    EXPECT_EQ(std::memcmp(b.c2w, a.c2w, sizeof a.c2w), 0) << "a pan does not turn the camera";
    EXPECT_NEAR(length((b.position - b.target) - (a.position - a.target)), 0.0f, 1e-5f * a.r);
  }
}

TEST(CameraNav, ZoomScalesTheDistanceWithinTheLimits) {
  const ViewCamera a = orbit(start_view(), 30.0, 20.0, kW, kH);
  const NavLimits limits = nav_limits(cornell().bounds);
  const ViewCamera in = zoom(a, -3.0, limits);
  EXPECT_NEAR(in.r, a.r * std::pow(1.1, -3.0), 1e-6 * a.r);
  EXPECT_EQ(in.target, a.target);
  EXPECT_NEAR(length(normalize(in.position - in.target) - column(a, 2)), 0.0f, 1e-6f);
  EXPECT_FLOAT_EQ(zoom(a, -100.0, limits).r, limits.min_r);
  EXPECT_FLOAT_EQ(zoom(a, 100.0, limits).r, limits.max_r);
}

TEST(CameraNav, LookAtFacesTheTarget) {
  const ViewCamera v = look_at(start_view(), {1.0f, 2.0f, 3.0f}, {0.0f, 0.5f, 0.0f}, nav_limits(cornell().bounds));
  expect_consistent(v);
  EXPECT_EQ(v.target, float3(0.0f, 0.5f, 0.0f));
  EXPECT_NEAR(length(v.position - float3(1.0f, 2.0f, 3.0f)), 0.0f, 1e-5f);
}

TEST(CameraNav, ProjectionIsTheInverseOfTheCameraRays) {
  const Camera c = resolve_camera(orbit(start_view(), 30.0, 20.0, kW, kH), kW, kH);
  for (auto [x, y] : {std::pair{0.5f, 0.5f}, std::pair{160.0f, 120.0f}, std::pair{319.5f, 17.25f}}) {
    const Ray r = camera_ray(c, x / kW, 1.0f - y / kH);
    float px = 0, py = 0;
    ASSERT_TRUE(project_to_pixel(c, kW, kH, r.org + r.dir * 3.0f, px, py));
    EXPECT_NEAR(px, x, 2e-3f);
    EXPECT_NEAR(py, y, 2e-3f);
  }
  float px = 0, py = 0;
  EXPECT_FALSE(project_to_pixel(c, kW, kH, c.position + c.to_camera, px, py)) << "behind the camera";
}

TEST(CameraNav, PansStopAtTheReachOfTheScenesCentreAsAPlacedCameraDoes) {
  // Two thousand of the largest pans a request makes, all one way: without a bound the target would leave for
  // 1e11 and the view degenerate; it stops on the sphere of the reach, the camera's offset unchanged.
  const NavLimits limits = nav_limits(cornell().bounds);
  const ViewCamera start = orbit(start_view(), 30.0, 20.0, kW, kH);
  ViewCamera v = start;
  for (int i = 0; i < 2000; ++i) v = pan(v, 1e5, -1e5, resolve_camera(v, kW, kH).tan_half_vfov, kH, limits);
  EXPECT_NEAR(length(v.target - limits.centre), limits.reach, 1e-3f * limits.reach);
  EXPECT_NEAR(length((v.position - v.target) - (start.position - start.target)), 0.0f, 1e-3f * start.r);
  EXPECT_EQ(look_at_problem(v.position, v.target, limits), "") << "where a pan stops, a camera may be placed";
  const Camera c = resolve_camera(v, kW, kH);
  EXPECT_TRUE(std::isfinite(c.position.x) && std::isfinite(c.position.y) && std::isfinite(c.position.z));
  // Beyond the reach, a placed camera is refused.
  const float3 beyond = limits.centre + float3(1.01f * limits.reach, 0.0f, 0.0f);
  EXPECT_NE(look_at_problem(beyond + float3(0.0f, 0.0f, 1.0f), beyond, limits).find("the target must lie within"),
            std::string::npos);
}

TEST(CameraNav, TheSavedFileResolvesToTheCameraTheViewRenders) {
  test::ScratchDir dir;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> px(-300.0, 300.0);
  ViewCamera v = start_view();
  const NavLimits limits = nav_limits(cornell().bounds);
  for (int i = 0; i < 50; ++i) {
    v = i % 3 == 0   ? pan(v, px(rng), px(rng), resolve_camera(v, kW, kH).tan_half_vfov, kH, limits)
        : i % 3 == 1 ? zoom(v, px(rng) / 100.0, limits)
                     : orbit(v, px(rng), px(rng), kW, kH);
    write_camera_settings_file(dir / "cam.txt", v);
    for (auto [w, h] : {std::pair{kW, kH}, std::pair{64, 48}, std::pair{100, 300}})
      expect_same_camera(resolve_camera(read_camera_settings_file(dir / "cam.txt"), w, h), resolve_camera(v, w, h));
    if (HasFailure()) return;
  }
}

}  // namespace
}  // namespace pt::live
