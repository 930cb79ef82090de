// Memory: the --memory report counts the scene's arrays and the per-pixel
// buffers exactly; the wavefront's queues are sized by the wave, not by the
// image; and a CBbunny render at 480x360 peaks under 64 MB of resident memory
// in every engine (the pathtracer binary, measured by the kernel via wait4).
#include <cstdio>
#include <filesystem>
#include <string>

#include "cli/memory_report.h"
#include "kernels/render/pixel_accumulator.h"
#include "support/run_process.h"
#include "support/stability_scenes.h"
#include "support/test_support.h"
#include "bvh/scene_bvh2.h"
#include "wavefront/engines.h"
#include "wavefront/streams.h"

namespace pt {
namespace {

const cli::MemoryLine& line(const cli::MemoryReport& r, const std::string& name) {
  for (const cli::MemoryLine& l : r.lines)
    if (l.structure == name) return l;
  static const cli::MemoryLine missing{"missing"};
  ADD_FAILURE() << "no line " << name;
  return missing;
}

template <class V>
void shrink(V& v) {
  v.shrink_to_fit();
  ASSERT_EQ(v.capacity(), v.size());
}

TEST(MemoryReport, CountsTheSceneArraysExactly) {
  Scene s = test::floor_under_square_light(0.5f);  // 8 vertices, 4 triangles, 2 materials, 1 light
  shrink(s.positions);
  shrink(s.normals);
  shrink(s.triangles);
  shrink(s.triangle_material);
  shrink(s.materials);
  shrink(s.area_lights);
  cli::MemoryReport r;
  cli::add_scene_memory(r, s);
  EXPECT_EQ(r.triangles, 4u);
  EXPECT_EQ(line(r, "scene: vertex positions").bytes, 8u * 12);
  EXPECT_EQ(line(r, "scene: vertex normals").bytes, 8u * 12);
  EXPECT_EQ(line(r, "scene: triangle indices").bytes, 4u * 12);
  EXPECT_EQ(line(r, "scene: triangle materials").bytes, 4u * 4);
  EXPECT_EQ(line(r, "scene: materials").bytes, 2u * sizeof(Material));
  EXPECT_EQ(line(r, "scene: lights").bytes, sizeof(AreaLight));
  EXPECT_EQ(r.total(), 8u * 24 + 4u * 16 + sizeof(AreaLight) + 2u * sizeof(Material));
}

/// A wavefront render of the floor scene at w x h and its report.
cli::MemoryReport wavefront_report(int w, int h) {
  Scene scene = test::floor_under_square_light(0.5f);
  RenderSettings rs = test::fixed_settings(w, h, 4);
  rs.max_depth = 3;
  rs.threads = 1;
  rs.seed = 0;
  SceneBvh2 accel(scene, Bvh2Mode::kMidpoint);
  wf::StageStats stages;
  RenderOutput out =
      wf::render_wavefront(scene, test::camera_above_floor(), rs, wf::Tracing{.bvh2 = &accel}, {}, {}, &stages);
  cli::MemoryReport r;
  cli::add_scene_memory(r, scene);
  cli::EngineFootprint engine{
      cli::Engine::kWavefront, "bvh2", {accel.bytes(), accel.bytes()}, stages.queue_bytes, stages.tracer_bytes};
  cli::add_render_memory(r, rs, scene, out, engine, "out.png");
  return r;
}

TEST(MemoryReport, PerPixelBuffersScaleWithTheImageAndQueuesWithTheWave) {
  // 64 x 48 pixels at 4 samples: more paths than one wave holds, as at 160 x 120.
  cli::MemoryReport small = wavefront_report(64, 48), large = wavefront_report(160, 120);
  for (const cli::MemoryReport* r : {&small, &large}) {
    size_t per_pixel = 0;
    for (const cli::MemoryLine& l : r->lines)
      if (l.scale == cli::MemoryScale::kPixel && !l.transient) per_pixel += l.bytes;
    // Accumulators, three pixel lists, film radiance + samples + variance.
    EXPECT_EQ(per_pixel, r->pixels * (sizeof(PixelAccumulator) + 3 * 4 + 12 + 4 + 4));
  }
  // One thread's queues hold one wave whatever the image size: path state,
  // two ray queues, hits, continuations, one shadow ray per path, and the
  // hit-point order's ray and hit queues with its cell and index per ray.
  const size_t wave = wf::WavefrontOptions{}.wave_paths;
  size_t queues = line(small, "wavefront: wave queues").bytes;
  EXPECT_EQ(queues, line(large, "wavefront: wave queues").bytes);
  size_t per_path = sizeof(wf::PathState::Item) + 4 * sizeof(wf::RayQueue::Item) + 2 * sizeof(wf::HitQueue::Item) +
                    sizeof(wf::ShadowQueue::Item) + 2 * sizeof(uint32_t);
  EXPECT_LE(queues, wave * per_path);
  EXPECT_GT(queues, 0u);
  // The queue tracer's answers: one byte per shadow ray of a wave (the BVH2
  // traces ray by ray: no lists).
  size_t tracer = line(small, "wavefront: queue tracer lists").bytes;
  EXPECT_EQ(tracer, line(large, "wavefront: queue tracer lists").bytes);
  EXPECT_LE(tracer, wave);
}

TEST(PeakMemory, CBbunnyAt480x360StaysUnder64MBInEveryEngine) {
  PT_REQUIRE_SHARED_SCENES();
#ifdef PT_ADDRESS_SANITIZER
  GTEST_SKIP() << "AddressSanitizer's shadow memory inflates the resident set";
#endif
  const size_t limit = 64'000'000;
  test::ScratchDir scratch;  // unique: test programs may run concurrently
  std::filesystem::path out = scratch / "memory.png";
  for (const char* engine : {"wavefront", "megakernel", "reference"}) {
    test::ProcessResult r =
        test::run_process(PT_PATHTRACER_BINARY,
                          {"--engine", engine, "-t", "2", "-s", "2", "-m", "5", "-a", "16", "0", "-r", "480", "360",
                           "--memory", "-q", "-f", out.string(), test::shared_scene("CBbunny.dae").string()},
                          std::filesystem::temp_directory_path(), 300);
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_LT(r.peak_rss_bytes, limit) << engine << "\n" << r.out;
    // The report's own peak (getrusage at its end) is the kernel's figure.
    size_t at = r.out.find("peak resident set size");
    ASSERT_NE(at, std::string::npos) << r.out;
    size_t reported = std::stoull(r.out.substr(at + 22));
    EXPECT_LE(reported, r.peak_rss_bytes);
    EXPECT_GT(reported, r.peak_rss_bytes / 2);
    std::printf("  %s: peak RSS %.2f MB (limit %.0f MB)\n", engine, r.peak_rss_bytes / 1e6, limit / 1e6);
  }
  std::filesystem::remove(out);
}

}  // namespace
}  // namespace pt
