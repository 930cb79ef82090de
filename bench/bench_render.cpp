// Render benchmark: whole renders of shared scenes by the three engines side
// by side in one run (wavefront, megakernel, scalar reference), all tracing
// through the same BVH4; the wavefront also without packets and without its
// queues by material kind (every shading kernel over every ray). CBgems and
// CBspheres_microfacet_al_ag mix materials; the others are one kind. Reports wall time, samples per second and rays per
// second (camera + bounce + shadow). The acceleration structure is built
// before timing. Google Benchmark JSON via --benchmark_out.
//
// Default settings are those of the course renderer's published timing:
// 480x360, -s 64 -l 4 -m 5, adaptive sampling off, 2 threads, the course
// renderer's framing (--cs184-framing). The SIMD engines run at the level
// PT_ISA names (default: the widest the CPU runs); the JSON context names it.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "bvh/scene_bvh4.h"
#include "io/camera_setup.h"
#include "io/collada_loader.h"
#include "reference/reference_renderer.h"
#include "wavefront/engines.h"

namespace {

using namespace pt;

struct LoadedScene {
  Scene scene;
  Camera camera;
  std::unique_ptr<SceneBvh4> bvh;
  std::unique_ptr<SceneBvh2> reference_accel;
};

RenderSettings course_comparison_settings() {
  return {.width = 480,
          .height = 360,
          .samples_per_pixel = 64,
          .light_samples = 4,
          .max_depth = 5,
          .adaptive_tolerance = 0.0f,
          .threads = 2};
}

const LoadedScene& scene(const std::string& name) {
  static std::vector<std::pair<std::string, std::unique_ptr<LoadedScene>>> cache;
  for (auto& [n, s] : cache)
    if (n == name) return *s;
  auto s = std::make_unique<LoadedScene>();
  s->scene = load_collada_file(std::filesystem::path(PT_SHARED_SCENES) / name).scene;
  RenderSettings rs = course_comparison_settings();
  s->camera = resolve_camera(s->scene, rs.width, rs.height, /*cs184_framing=*/true);
  s->bvh = std::make_unique<SceneBvh4>(s->scene);
  s->reference_accel = std::make_unique<SceneBvh2>(s->scene, Bvh2Mode::kMidpoint);
  cache.emplace_back(name, std::move(s));
  return *cache.back().second;
}

RenderOutput render(const std::string& engine, const LoadedScene& s, const RenderSettings& rs) {
  const wf::Tracing tracing{.bvh4 = s.bvh.get()};
  if (engine == "wavefront") return wf::render_wavefront(s.scene, s.camera, rs, tracing);
  if (engine == "wavefront_single") {  // what the queue tracer buys
    wf::WavefrontOptions o;
    o.trace = wf::TraceMode::kSingle;
    return wf::render_wavefront(s.scene, s.camera, rs, tracing, o);
  }
  if (engine == "wavefront_unsorted") {  // every shading kernel over every ray: what material queues buy
    wf::WavefrontOptions o;
    o.sort_by_material = false;
    return wf::render_wavefront(s.scene, s.camera, rs, tracing, o);
  }
  if (engine == "megakernel") return wf::render_megakernel(s.scene, s.camera, rs, tracing);
  return reference::render_reference(s.scene, *s.reference_accel, s.camera, rs);
}

void bench_render(benchmark::State& state, const std::string& scene_name, const std::string& engine, int threads) {
  if (!std::filesystem::is_directory(PT_SHARED_SCENES)) {
    state.SkipWithError("../shared/scenes/cs184 absent");
    return;
  }
  const LoadedScene& s = scene(scene_name);
  RenderSettings rs = course_comparison_settings();
  rs.threads = threads;
  RenderStats last;
  for (auto _ : state) {
    RenderOutput out = render(engine, s, rs);
    state.SetIterationTime(out.stats.seconds);
    last = out.stats;
    benchmark::DoNotOptimize(out.film.radiance.data());
  }
  state.counters["seconds"] = last.seconds;
  state.counters["samples_per_s"] = last.samples / last.seconds;
  state.counters["mrays_per_s"] = last.rays() / last.seconds / 1e6;
  state.counters["rays"] = static_cast<double>(last.rays());
  state.counters["camera_rays"] = static_cast<double>(last.camera_rays);
  state.counters["bounce_rays"] = static_cast<double>(last.bounce_rays);
  state.counters["shadow_rays"] = static_cast<double>(last.shadow_rays);
}

void register_benchmarks() {
  for (const char* scene_name :
       {"CBbunny.dae", "CBspheres_lambertian.dae", "CBcoil.dae", "CBgems.dae", "CBspheres_microfacet_al_ag.dae"})
    for (const char* engine : {"wavefront", "wavefront_single", "wavefront_unsorted", "megakernel", "reference"}) {
      std::string name = std::string("render/") + scene_name + "/" + engine + "/threads:2";
      benchmark::RegisterBenchmark(name.c_str(), bench_render, std::string(scene_name), std::string(engine), 2)
          ->Unit(benchmark::kSecond)
          ->UseManualTime()
          ->Iterations(1);
    }
}

}  // namespace

int main(int argc, char** argv) {
  register_benchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::AddCustomContext(
      "isa", std::string(isa_name(active_isa())) + ", " + std::to_string(isa_lanes(active_isa())) + " lanes");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
