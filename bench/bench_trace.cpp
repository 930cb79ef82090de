// bench_trace: the ray tracing benchmark (Google Benchmark, JSON with
// --benchmark_out). Per scene, every tracer in the same process on the same
// rays in the same order, 1 and 2 threads, as rays/s counters. Ray sets:
// primary camera rays (Morton order); diffuse and shadow rays from their hits,
// in the camera rays' order and shuffled; and the bounce and shadow queues of
// depths 1-4 of a real wavefront render of the scene (captured_queues.h), in
// the render's order and queues. Tracers: this BVH4 (single rays with
// Moller-Trumbore and watertight leaves; the queue tracer over each queue;
// sorted single rays for incoherent
// batches), the reference binary BVH, brute force on small scenes, and
// Embree 3 built with high and default quality, with every method it has
// (single rays, packets of 4/8/16, streams of records and of arrays, with the
// incoherent and the coherent flag). Plus build times and memory. Every
// tracer is validated ray by ray before it is timed.
//   bench_trace [--quick] [--export-rays DIR] [--collapse-costs=N,L,B,M] [--presplit=B] [benchmark flags]
// --quick: two small scenes and fewer rays (a smoke run); --export-rays:
// write every scene's triangles and ray sets for trace_rays, then exit;
// --collapse-costs: the BVH4 collapse's node, leaf and block costs and
// largest leaf (bvh4_collapse.h; default 1,0.7,0.3,16, the block 0.6 in trees
// that fit in L1; given costs hold for every scene), and --presplit the
// pre-splitting budget (extra references per triangle, presplit.h), for tuning.
// 1-thread rates are over thread CPU time, 2-thread rates over wall time.
// The kernels run at the level PT_ISA names (default: the widest the CPU
// runs), Embree restricted to the same instruction set; the JSON context
// names both.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <memory>

#include <oneapi/tbb/task_arena.h>

#include "bench_fixture.h"
#include "bench_scenes.h"
#include "ray_driver.h"
#include "io/ray_files.h"

namespace pt::bench {
namespace {

struct SceneSpec {
  std::string label, file;
  int subdivide = 0;
  bool small = false;  ///< brute force joins in
};

std::vector<SceneSpec> scene_list(bool quick) {
  if (quick) return {{"CBgems", "CBgems.dae", 0, true}, {"CBbunny", "CBbunny.dae"}};
  return {{"CBgems", "CBgems.dae", 0, true},
          {"teapot", "teapot.dae", 0, true},
          {"CBcoil", "CBcoil.dae"},
          {"CBbunny", "CBbunny.dae"},
          {"bunny", "bunny.dae"},
          {"CBbunny_x4", "CBbunny.dae", 1},
          {"CBbunny_x16", "CBbunny.dae", 2},
          {"CBbunny_x64", "CBbunny.dae", 3},
          {"CBbunny_x256", "CBbunny.dae", 4}};
}

FixtureOptions g_options;
std::map<std::string, std::unique_ptr<SceneFixture>> g_fixtures;

/// The scene's fixture, created on first use (nullptr when the scene file is absent).
SceneFixture* fixture(const SceneSpec& spec) {
  auto it = g_fixtures.find(spec.label);
  if (it != g_fixtures.end()) return it->second.get();
  std::unique_ptr<SceneFixture> f;
  if (std::optional<Scene> s = load_triangle_scene(spec.file))
    f = std::make_unique<SceneFixture>(spec.label, subdivide_scene(*s, spec.subdivide), g_options);
  return (g_fixtures[spec.label] = std::move(f)).get();
}

/// The sets of every scene, in the fixture's order (the last two only when
/// the render's queues are captured).
const std::vector<std::string> kSetNames = {"primary",         "diffuse",       "shadow",       "diffuse_shuffled",
                                            "shadow_shuffled", "bounce_queues", "shadow_queues"};

void trace_benchmark(benchmark::State& state, SceneSpec spec, std::string set_name, std::string tracer, int threads) {
  SceneFixture* f = fixture(spec);
  if (!f) return state.SkipWithError(("scene file absent: " + spec.file).c_str());
  const int set = f->set_index(set_name);
  if (set < 0) return state.SkipWithError((set_name + " is not available").c_str());
  const TracerEntry* t = nullptr;
  for (const TracerEntry& e : f->tracers()) t = e.name == tracer ? &e : t;
  if (!t) return state.SkipWithError((tracer + " is not available").c_str());
  if (const std::string& err = f->validate(*t, set); !err.empty()) return state.SkipWithError(err.c_str());
  const RaySet& rays = f->sets()[set];
  size_t n = std::min(rays.rays.size(), t->max_rays);
  std::vector<Hit> hits(n);
  std::vector<uint8_t> blocked(n);
  for (auto _ : state) {
    run_tracer(*t, rays, set, n, threads, hits.data(), blocked.data());
    benchmark::DoNotOptimize(hits.data());
    benchmark::DoNotOptimize(blocked.data());
  }
  state.counters["rays_per_s"] = benchmark::Counter(double(n) * state.iterations(), benchmark::Counter::kIsRate);
  state.counters["rays"] = double(n);
  state.counters["queues"] = double(rays.queue_ends.size());
  state.counters["mismatches"] = double(f->mismatches(*t, set));
  if (tracer.rfind("bvh4", 0) == 0) {
    TraversalCounters c = f->bvh4_work(set, tracer == "bvh4_watertight", tracer == "bvh4_queue");
    state.counters["nodes_per_ray"] = double(c.nodes) / rays.rays.size();
    state.counters["triangles_per_ray"] = double(c.primitives) / rays.rays.size();
  }
}

void build_bvh4_benchmark(benchmark::State& state, SceneSpec spec, int threads) {
  SceneFixture* f = fixture(spec);
  if (!f) return state.SkipWithError(("scene file absent: " + spec.file).c_str());
  Bvh4Options o = g_options.bvh4;
  o.threads = threads;
  Bvh4BuildStats stats;
  for (auto _ : state) {
    Bvh4 bvh = build_bvh4(f->scene().positions, f->scene().triangles, o, &stats);
    state.SetIterationTime(stats.build_ms / 1000.0);
  }
  state.counters["triangles"] = stats.triangles;
  state.counters["bytes_per_triangle"] = stats.bytes_per_triangle;
  state.counters["nodes"] = stats.nodes;
  state.counters["leaves"] = stats.leaves;
  state.counters["blocks"] = stats.blocks;
  state.counters["depth"] = stats.depth;
  state.counters["sah_cost"] = stats.sah_cost;
  state.counters["references"] = stats.references;
}

#ifdef PT_HAVE_EMBREE
void build_embree_benchmark(benchmark::State& state, SceneSpec spec, RTCBuildQuality quality, int threads) {
  SceneFixture* f = fixture(spec);
  if (!f) return state.SkipWithError(("scene file absent: " + spec.file).c_str());
  int64_t bytes = 0;
  for (auto _ : state) {
    double ms = 0;
    arena_of(threads).execute([&] {
      EmbreeTracer t(f->scene(), quality);
      ms = t.build_ms();
      bytes = t.bytes();
    });
    state.SetIterationTime(ms / 1000.0);
  }
  state.counters["triangles"] = double(f->scene().triangles.size());
  state.counters["bytes_per_triangle"] = double(bytes) / double(f->scene().triangles.size());
}
#endif

std::vector<std::string> tracer_names(const SceneSpec& spec, const std::string& set) {
  std::vector<std::string> names = {"bvh4", "bvh4_queue", "bvh4_watertight", "bvh2_midpoint", "bvh4_incoherent"};
  if (spec.small) names.push_back("brute_force");
#ifdef PT_HAVE_EMBREE
  for (const char* build : {"embree_high_", "embree_default_"})
    for (EmbreeMethod m : kEmbreeMethods) names.push_back(build + std::string(embree_method_name(m)));
#endif
  return names;
}

/// The targets compare this BVH4 and Embree at 1 and 2 threads; the others run on 1.
bool runs_on_two_threads(const std::string& tracer) {
  return (tracer.rfind("bvh4", 0) == 0 && tracer != "bvh4_watertight") || tracer.rfind("embree", 0) == 0;
}

void register_benchmarks(const std::vector<SceneSpec>& specs) {
  for (const SceneSpec& spec : specs) {
    for (int threads : {1, 2})
      benchmark::RegisterBenchmark(("build/" + spec.label + "/bvh4/threads:" + std::to_string(threads)).c_str(),
                                   build_bvh4_benchmark, spec, threads)
          ->UseManualTime()
          ->Unit(benchmark::kMillisecond);
#ifdef PT_HAVE_EMBREE
    for (int threads : {1, 2})
      for (auto [name, quality] :
           {std::pair{"embree_high", RTC_BUILD_QUALITY_HIGH}, {"embree_default", RTC_BUILD_QUALITY_MEDIUM}})
        benchmark::RegisterBenchmark(
            ("build/" + spec.label + "/" + name + "/threads:" + std::to_string(threads)).c_str(),
            build_embree_benchmark, spec, quality, threads)
            ->UseManualTime()
            ->Unit(benchmark::kMillisecond);
#endif
    for (const std::string& set : kSetNames)
      for (const std::string& tracer : tracer_names(spec, set))
        for (int threads : {1, 2}) {
          if (threads == 2 && !runs_on_two_threads(tracer)) continue;
          std::string name = "trace/" + spec.label + "/" + set + "/" + tracer + "/threads:" + std::to_string(threads);
          auto* b = benchmark::RegisterBenchmark(name.c_str(), trace_benchmark, spec, set, tracer, threads);
          b->Unit(benchmark::kMillisecond);
          // One thread: rates over the thread's CPU time, which other processes on a
          // shared machine do not inflate. Two threads: over wall-clock time.
          if (threads == 2) b->UseRealTime();
        }
  }
}

int export_rays(const std::vector<SceneSpec>& specs, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  for (const SceneSpec& spec : specs) {
    SceneFixture* f = fixture(spec);
    if (!f) continue;
    write_triangle_file(dir / (spec.label + ".tris"), f->scene());
    for (const RaySet& set : f->sets()) write_ray_file(dir / (spec.label + "_" + set.name + ".rays"), set.rays);
    std::cout << "wrote " << spec.label << " (" << f->scene().triangles.size() << " triangles)\n";
  }
  return 0;
}

}  // namespace
}  // namespace pt::bench

int main(int argc, char** argv) {
  using namespace pt::bench;
  bool quick = false;
  std::string export_dir, collapse, presplit;
  std::vector<char*> rest = {argv[0]};
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--quick")) quick = true;
    else if (!std::strcmp(argv[i], "--export-rays") && i + 1 < argc) export_dir = argv[++i];
    else if (!std::strncmp(argv[i], "--collapse-costs=", 17)) collapse = argv[i] + 17;
    else if (!std::strncmp(argv[i], "--presplit=", 11)) presplit = argv[i] + 11;
    else rest.push_back(argv[i]);
  }
  if (quick) {
    g_options.width = 256;
    g_options.height = 192;
    g_options.brute_force_rays = 4096;
  }
  if (!collapse.empty()) {
    pt::CollapseCosts& c = g_options.bvh4.collapse;
    g_options.bvh4.l1_resident_block_cost = 0.0f;  // the costs as given, for every scene
    if (std::sscanf(collapse.c_str(), "%f,%f,%f,%u", &c.node, &c.leaf, &c.block, &c.max_leaf_size) != 4) {
      std::cerr << "error: --collapse-costs wants NODE,LEAF,BLOCK,MAX_LEAF_SIZE, not '" << collapse << "'\n";
      return 2;
    }
  }
  if (!presplit.empty()) {
    float& budget = g_options.bvh4.presplit_budget;
    if (std::sscanf(presplit.c_str(), "%f", &budget) != 1 || !(budget >= 0.0f && budget <= 16.0f)) {
      std::cerr << "error: --presplit wants a budget from 0 to 16 extra references per triangle, not '" << presplit
                << "'\n";
      return 2;
    }
  }
  std::vector<SceneSpec> specs = scene_list(quick);
  if (!export_dir.empty()) return export_rays(specs, export_dir);
  int n = static_cast<int>(rest.size());
  benchmark::Initialize(&n, rest.data());
  if (benchmark::ReportUnrecognizedArguments(n, rest.data())) return 1;
  benchmark::AddCustomContext(
      "rays", std::to_string(g_options.width) + "x" + std::to_string(g_options.height) + " primary rays per scene");
  benchmark::AddCustomContext("bvh4_layout", "128-byte nodes, 160-byte blocks of 4 triangles");
  benchmark::AddCustomContext("isa", std::string(pt::isa_name(pt::active_isa())) + ", " +
                                         std::to_string(pt::isa_lanes(pt::active_isa())) + " lanes");
#ifdef PT_HAVE_EMBREE
  benchmark::AddCustomContext("embree", EmbreeTracer::version_and_isa());
#endif
  register_benchmarks(specs);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  g_fixtures.clear();
  return 0;
}
