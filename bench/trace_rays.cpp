// trace_rays: time this BVH4 on exactly the rays another tracer traced.
//   trace_rays TRIS RAYS [--threads N] [--reps N] [--hits OUT]
// Reads a triangle file and a ray file (formats in ray_files.h), builds the
// BVH4, traces every ray closest-hit on 1 thread and on N threads (default 2):
// a warm-up pass, then the median of --reps passes (default 7, at least 7),
// excluding file I/O and the build. Prints one JSON line per thread count:
//   {"threads":1,"isa":"avx2","mrays_per_s":...,"hits":...,"sum_t":...,"build_ms":...,"rays":...,
//    "triangles":...}
// The kernels run at the level --isa (or PT_ISA) names, default the widest
// this CPU runs.
// --hits OUT writes float32 t, uint32 primitive per ray (the last pass).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bvh/scene_bvh4.h"
#include "io/scene_error.h"
#include "ray_driver.h"
#include "ray_files.h"

namespace {

using namespace pt;

struct Pass {
  double seconds;
  size_t hits;
  double sum_t;
};

Pass trace_once(const SceneBvh4& bvh, const std::vector<Ray>& rays, std::vector<Hit>& hits, int threads) {
  auto start = std::chrono::steady_clock::now();
  bench::run_chunks(rays.size(), threads, [&](size_t b, size_t e) {
    bvh.intersect_each(std::span<const Ray>(rays).subspan(b, e - b), std::span<Hit>(hits).subspan(b, e - b));
  });
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Pass p{s, 0, 0.0};
  for (const Hit& h : hits)
    if (h.valid()) {
      ++p.hits;
      p.sum_t += h.t;
    }
  return p;
}

void report(int threads, const std::vector<double>& seconds, const Pass& last, size_t rays, size_t triangles,
            double build_ms) {
  std::vector<double> s = seconds;
  std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
  double median = s[s.size() / 2];
  std::printf(
      "{\"threads\":%d,\"isa\":\"%s\",\"mrays_per_s\":%.4f,\"hits\":%zu,\"sum_t\":%.17g,\"build_ms\":%.3f,"
      "\"rays\":%zu,\"triangles\":%zu,\"passes\":%zu}\n",
      threads, std::string(isa_name(active_isa())).c_str(), rays / median / 1e6, last.hits, last.sum_t, build_ms, rays,
      triangles, seconds.size());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Traces a ray file against a triangle file with the BVH4 and prints throughput as JSON lines."};
  std::string tris_path, rays_path, hits_path, isa = "auto";
  int threads = 2, reps = 7;
  app.add_option("TRIS", tris_path, "Triangles: float32 x,y,z per vertex, 9 floats per triangle")->required();
  app.add_option("RAYS", rays_path, "Rays: float32 ox,oy,oz,tmin,dx,dy,dz,tmax per ray")->required();
  app.add_option("--threads", threads, "Largest thread count (1 and this are timed)")->check(CLI::Range(1, 256));
  app.add_option("--reps", reps, "Timed passes per thread count (at least 7)")->check(CLI::Range(1, 100000));
  app.add_option("--hits", hits_path, "Write float32 t, uint32 primitive per ray");
  app.add_option("--isa", isa, "Instruction set: auto, sse4.2, avx2, avx512 or neon (also PT_ISA)");
  CLI11_PARSE(app, argc, argv);
  reps = std::max(reps, 7);
  try {
    set_active_isa(app.count("--isa") ? resolve_isa(isa) : active_isa());
    Scene scene = bench::read_triangle_file(tris_path);
    std::vector<Ray> rays = bench::read_ray_file(rays_path);
    Bvh4Options options;
    options.threads = threads;
    SceneBvh4 bvh(scene, options);
    std::vector<Hit> hits(rays.size());
    std::vector<int> counts = {1};
    if (threads > 1) counts.push_back(threads);
    for (int t : counts) {
      trace_once(bvh, rays, hits, t);  // warm-up
      std::vector<double> seconds;
      Pass last{};
      for (int r = 0; r < reps; ++r) {
        last = trace_once(bvh, rays, hits, t);
        seconds.push_back(last.seconds);
      }
      report(t, seconds, last, rays.size(), scene.triangles.size(), bvh.stats().build_ms);
    }
    if (!hits_path.empty()) bench::write_hit_file(hits_path, hits);
  } catch (const IsaError& e) {
    std::fprintf(stderr, "error: %s%s\n", app.count("--isa") ? "--isa: " : "", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
