// Random numbers are keyed by (pixel, sample, bounce, dimension), never by
// thread or work order, so an image is the same bit for bit whatever the
// thread count: checked on the Cornell scene with adaptive sampling on (so the
// stopping decisions must agree too) and on a sky-lit scene, for every engine.
// Exact: one differing bit fails; no statistics are involved.
#include <cstring>
#include <string>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "io/camera_setup.h"
#include "support/scene_builders.h"
#include "support/test_support.h"

namespace pt {
namespace {

void expect_identical(const Film& a, const Film& b, const std::string& what) {
  ASSERT_EQ(a.radiance.size(), b.radiance.size()) << what;
  EXPECT_EQ(std::memcmp(a.radiance.data(), b.radiance.data(), a.radiance.size() * sizeof(float3)), 0)
      << what << ": radiance differs";
  EXPECT_EQ(a.samples, b.samples) << what << ": samples differ";
}

void expect_thread_count_invariant(const Scene& s, const Camera& camera, RenderSettings rs) {
  for (const test::EngineUnderTest& e : test::engines_under_test()) {
    rs.threads = 1;
    const Film one = e.render(s, camera, rs).film;
    rs.threads = 2;
    expect_identical(one, e.render(s, camera, rs).film, e.name + " with 2 threads");
  }
}

TEST(ThreadDeterminism, CornellSceneWithAdaptiveSampling) {
  const Scene s = load_collada_file(test::project_scene("cornell_spheres.dae")).scene;
  RenderSettings rs = test::fixed_settings(40, 30, 32);  // several 16 x 16 tiles
  rs.max_depth = 4;
  rs.adaptive_batch = 8;
  rs.adaptive_tolerance = 0.1f;
  rs.light_samples = 2;
  expect_thread_count_invariant(s, resolve_camera(s, rs.width, rs.height), rs);
}

TEST(ThreadDeterminism, SkyLitSceneWithHemisphereSampling) {
  Scene s;
  const float h = 5.0f;
  uint32_t m = test::add_material(s, float3{0.6f, 0.5f, 0.4f});
  test::add_quad(s, {-h, 0, -h}, {h, 0, -h}, {h, 0, h}, {-h, 0, h}, {0, 1, 0}, m);
  s.spheres.push_back({{0, 0.5f, 0}, 0.5f, m});
  s.sky = SkyLight{float3{0.8f, 0.9f, 1.0f}};
  test::finish_scene(s);
  RenderSettings rs = test::fixed_settings(37, 21, 16);
  rs.max_depth = 3;
  rs.direct = DirectLighting::kHemisphere;
  expect_thread_count_invariant(s, test::look_at({1, 1.5f, 2.5f}, {0, 0.4f, 0}, 0.8f, 0.5f), rs);
}

}  // namespace
}  // namespace pt
