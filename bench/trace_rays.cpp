// trace_rays: time this BVH4 on exactly the rays another tracer traced.
//   trace_rays TRIS RAYS [--occluded] [--single] [--queue N] [--embree] [--threads N] [--reps N] [--hits OUT]
// Reads a triangle file and a ray file (formats in io/ray_files.h), builds the
// BVH4, and traces every ray, closest hit (or any hit with --occluded), in the
// file's order: in queues of --queue rays (default 4096, the wavefront's
// wave) through the queue tracer, or with --single ray by ray. On 1 thread
// and on N threads (default 2; queues spread over the threads): a warm-up
// pass, then the median of --reps passes (default 7, at least 7), excluding
// file I/O and the build; 1 thread over the thread's CPU time, more over
// wall time. Prints one JSON line per thread count:
//   {"threads":1,"isa":"avx2","method":"queue","mrays_per_s":...,"hits":...,"sum_t":...,"build_ms":...,
//    "rays":...,"triangles":...}
// (with --occluded, "hits" counts blocked rays and sum_t is 0).
// --embree then times every Embree method (embree_tracer.h), high-quality and
// default builds, on the same queues in the same order: one line each, with
// "method":"embree_high_packet16" and so on.
// The kernels run at the level --isa (or PT_ISA) names, default the widest
// this CPU runs.
// --count then prints the work per ray of one more, untimed pass:
// {"isa":"avx2","method":"queue_counts","nodes_per_ray":...,"triangles_per_ray":...}
// (or "single_counts"; ray-node and ray-triangle tests, the counters
// bench_trace reports). Coherent sets count nothing, so a coherent queue is
// counted as the stream traces it (closest hits: ray by ray).
// --hits OUT writes float32 t, uint32 primitive per ray (the last pass; a
// blocked ray of --occluded: t = 0, primitive 0; an unblocked one: t = tmax,
// 0xFFFFFFFF).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <span>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <oneapi/tbb/enumerable_thread_specific.h>

#include "bvh/scene_bvh4.h"
#include "io/scene_error.h"
#ifdef PT_HAVE_EMBREE
#include "embree_tracer.h"
#endif
#include "line_aligned_vector.h"
#include "ray_driver.h"
#include "bench_queries.h"
#include "io/ray_files.h"

namespace {

using namespace pt;

using bench::LineAlignedVector;

/// The rays as arrays (the queue tracer's input), and its outputs.
struct Queues {
  LineAlignedVector<float> field[8];  // ox, oy, oz, tmin, dx, dy, dz, tmax
  LineAlignedVector<float> t, u, v;
  LineAlignedVector<uint32_t> prim;
  std::vector<uint8_t> blocked;

  explicit Queues(const std::vector<Ray>& rays) {
    for (LineAlignedVector<float>& f : field) f.resize(rays.size());
    for (size_t i = 0; i < rays.size(); ++i) {
      const Ray& r = rays[i];
      const float v8[8] = {r.org.x, r.org.y, r.org.z, r.tmin, r.dir.x, r.dir.y, r.dir.z, r.tmax};
      for (int k = 0; k < 8; ++k) field[k][i] = v8[k];
    }
    t.resize(rays.size()), u.resize(rays.size()), v.resize(rays.size()), prim.resize(rays.size());
    blocked.resize(rays.size());
  }
  RayArrays rays(size_t b, size_t e) const {
    return {{field[0].data() + b, field[1].data() + b, field[2].data() + b},
            {field[4].data() + b, field[5].data() + b, field[6].data() + b},
            field[3].data() + b,
            field[7].data() + b,
            e - b};
  }
  HitArrays hits(size_t b) { return {t.data() + b, u.data() + b, v.data() + b, prim.data() + b}; }
};

struct Pass {
  double seconds;
  size_t hits;
  double sum_t;
};

double thread_cpu_seconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return double(ts.tv_sec) + 1e-9 * double(ts.tv_nsec);
}

struct Setup {
  bool occluded = false, single = false;
  size_t queue = 4096;
};

/// Runs trace(first, last) over queues [0, queues): on one thread, or spread
/// over `threads`; returns the seconds it took (1 thread: the thread's CPU
/// time, which other processes on a shared machine do not inflate, as
/// bench_trace; more: wall time).
template <class Trace>
double time_queues(size_t queues, int threads, Trace&& trace) {
  auto start = std::chrono::steady_clock::now();
  const double cpu_start = thread_cpu_seconds();
  if (threads <= 1) {
    enable_flush_denormals_to_zero();
    trace(size_t{0}, queues);
  } else {
    bench::arena_of(threads).execute([&] {
      oneapi::tbb::parallel_for(oneapi::tbb::blocked_range<size_t>(0, queues), [&](const auto& r) {
        enable_flush_denormals_to_zero();
        trace(r.begin(), r.end());
      });
    });
  }
  return threads <= 1 ? thread_cpu_seconds() - cpu_start
                      : std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The pass's counts: blocked rays, or hits and the sum of their t.
Pass count(double seconds, const std::vector<Hit>& hits, const std::vector<uint8_t>& blocked, bool occluded) {
  Pass p{seconds, 0, 0.0};
  if (occluded) {
    for (uint8_t b : blocked) p.hits += b;
    return p;
  }
  for (const Hit& h : hits)
    if (h.valid()) {
      ++p.hits;
      p.sum_t += h.t;
    }
  return p;
}

Pass trace_once(const SceneBvh4& bvh, const std::vector<Ray>& rays, Queues& q, std::vector<Hit>& hits, int threads,
                const Setup& setup) {
  static oneapi::tbb::enumerable_thread_specific<QueueScratch> scratch;
  const size_t queues = (rays.size() + setup.queue - 1) / setup.queue;
  double s = time_queues(queues, threads, [&](size_t first, size_t last) {
    for (size_t k = first; k < last; ++k) {
      const size_t b = k * setup.queue, e = std::min(rays.size(), b + setup.queue);
      if (setup.single) {
        std::span<const Ray> in = std::span<const Ray>(rays).subspan(b, e - b);
        if (setup.occluded)
          bench::bench_queries().occluded_each(bvh, in, std::span<uint8_t>(q.blocked).subspan(b, e - b));
        else bench::bench_queries().intersect_each(bvh, in, std::span<Hit>(hits).subspan(b, e - b));
      } else if (setup.occluded) {
        bvh.occluded_queue(q.rays(b, e), q.blocked.data() + b, scratch.local());
      } else {
        bvh.intersect_queue(q.rays(b, e), q.hits(b), scratch.local());
      }
    }
  });
  if (!setup.single && !setup.occluded)
    for (size_t i = 0; i < rays.size(); ++i) hits[i] = Hit{q.t[i], q.u[i], q.v[i], q.prim[i]};
  return count(s, hits, q.blocked, setup.occluded);
}

/// One untimed pass of the method with counters: its line of nodes and
/// triangles tested per ray.
void report_counts(const SceneBvh4& bvh, const std::vector<Ray>& rays, Queues& q, std::vector<Hit>& hits,
                   const Setup& setup) {
  QueueScratch scratch;
  TraversalCounters c;
  for (size_t b = 0; b < rays.size(); b += setup.queue) {
    const size_t e = std::min(rays.size(), b + setup.queue);
    if (setup.single) {
      for (size_t i = b; i < e; ++i) {
        if (setup.occluded) q.blocked[i] = bvh.occluded(rays[i], &c);
        else bvh.intersect(rays[i], hits[i], &c);
      }
    } else if (setup.occluded) {
      std::fill(q.blocked.begin() + b, q.blocked.begin() + e, 0);
      bvh.occluded_queue(q.rays(b, e), q.blocked.data() + b, scratch, &c);
    } else {
      bvh.intersect_queue(q.rays(b, e), q.hits(b), scratch, &c);
    }
  }
  const double n = double(std::max<size_t>(rays.size(), 1));
  std::printf("{\"isa\":\"%s\",\"method\":\"%s_counts\",\"nodes_per_ray\":%.4f,\"triangles_per_ray\":%.4f}\n",
              std::string(isa_name(active_isa())).c_str(), setup.single ? "single" : "queue", double(c.nodes) / n,
              double(c.primitives) / n);
  std::fflush(stdout);
}

/// Times `pass` (a warm-up, then the median of `reps`) and prints its line.
template <class PassFn>
void time_and_report(int threads, const std::string& method, int reps, size_t rays, size_t triangles, double build_ms,
                     PassFn&& pass);

#ifdef PT_HAVE_EMBREE
/// Every Embree method over the same queues, with its high-quality and its
/// default build: one line each per thread count.
void time_embree(const Scene& scene, const std::vector<Ray>& rays, const Setup& setup,
                 const std::vector<int>& thread_counts, int reps) {
  bench::RaySet set{"file", setup.occluded, rays, {}};
  for (size_t end = setup.queue; end < rays.size(); end += setup.queue) set.queue_ends.push_back(end);
  set.queue_ends.push_back(rays.size());
  const bench::EmbreeRays converted = bench::convert_rays(set);
  std::vector<Hit> hits(rays.size());
  std::vector<uint8_t> blocked(rays.size());
  for (auto [name, quality] :
       {std::pair{"embree_high", RTC_BUILD_QUALITY_HIGH}, {"embree_default", RTC_BUILD_QUALITY_MEDIUM}}) {
    std::unique_ptr<bench::EmbreeTracer> embree;
    bench::arena_of(thread_counts.back()).execute([&] {
      embree = std::make_unique<bench::EmbreeTracer>(scene, quality);
    });
    for (bench::EmbreeMethod m : bench::kEmbreeMethods)
      for (int t : thread_counts)
        time_and_report(t, std::string(name) + "_" + bench::embree_method_name(m), reps, rays.size(),
                        scene.triangles.size(), embree->build_ms(), [&] {
                          double s = time_queues(set.queue_ends.size(), t, [&](size_t first, size_t last) {
                            const size_t b = first == 0 ? 0 : set.queue_ends[first - 1];
                            embree->trace(m, converted, b, set.queue_ends[last - 1], hits.data(), blocked.data());
                          });
                          return count(s, hits, blocked, setup.occluded);
                        });
  }
}
#endif

void report(int threads, const char* method, const std::vector<double>& seconds, const Pass& last, size_t rays,
            size_t triangles, double build_ms) {
  std::vector<double> s = seconds;
  std::nth_element(s.begin(), s.begin() + s.size() / 2, s.end());
  double median = s[s.size() / 2];
  std::printf(
      "{\"threads\":%d,\"isa\":\"%s\",\"method\":\"%s\",\"mrays_per_s\":%.4f,\"hits\":%zu,\"sum_t\":%.17g,"
      "\"build_ms\":%.3f,\"rays\":%zu,\"triangles\":%zu,\"passes\":%zu}\n",
      threads, std::string(isa_name(active_isa())).c_str(), method, rays / median / 1e6, last.hits, last.sum_t,
      build_ms, rays, triangles, seconds.size());
  std::fflush(stdout);
}

template <class PassFn>
void time_and_report(int threads, const std::string& method, int reps, size_t rays, size_t triangles, double build_ms,
                     PassFn&& pass) {
  pass();  // warm-up
  std::vector<double> seconds;
  Pass last{};
  for (int r = 0; r < reps; ++r) {
    last = pass();
    seconds.push_back(last.seconds);
  }
  report(threads, method.c_str(), seconds, last, rays, triangles, build_ms);
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
  Setup setup;
  app.add_flag("--occluded", setup.occluded, "Any-hit (occlusion) queries instead of closest hits");
  app.add_flag("--single", setup.single, "Trace ray by ray instead of through the queue tracer");
  app.add_option("--queue", setup.queue,
                 "Rays per queue for the queue tracer (4096: its largest part; the wavefront's queues "
                 "come from waves of 8192 paths)")
      ->check(CLI::Range(1, 1 << 24));
  app.add_option("--isa", isa, "Instruction set: auto, sse4.2, avx2, avx512 or neon (also PT_ISA)");
  bool counts_wanted = false;
  app.add_flag("--count", counts_wanted, "Then print nodes and triangles tested per ray of one untimed pass");
  bool embree = false;
  app.add_flag("--embree", embree,
               "Then time every Embree method (single rays, packets, streams; high and default builds) on the same "
               "queues, one line each");
  CLI11_PARSE(app, argc, argv);
  reps = std::max(reps, 7);
  try {
    set_active_isa(app.count("--isa") ? resolve_isa(isa) : active_isa());
    Scene scene = read_triangle_file(tris_path);
    std::vector<Ray> rays = read_ray_file(rays_path);
    Bvh4Options options;
    options.threads = threads;
    SceneBvh4 bvh(scene, options);
    std::vector<Hit> hits(rays.size());
    Queues queues(rays);
    std::vector<int> counts = {1};
    if (threads > 1) counts.push_back(threads);
    const char* method = setup.single ? "single" : "queue";
    for (int t : counts)
      time_and_report(t, method, reps, rays.size(), scene.triangles.size(), bvh.stats().build_ms,
                      [&] { return trace_once(bvh, rays, queues, hits, t, setup); });
    if (setup.occluded)
      for (size_t i = 0; i < rays.size(); ++i)
        hits[i] = queues.blocked[i] ? Hit{0.0f, 0.0f, 0.0f, 0} : Hit{rays[i].tmax, 0.0f, 0.0f, kInvalidId};
    if (!hits_path.empty()) write_hit_file(hits_path, hits);
    if (counts_wanted) report_counts(bvh, rays, queues, hits, setup);
    if (embree) {
#ifdef PT_HAVE_EMBREE
      time_embree(scene, rays, setup, counts, reps);
#else
      std::fprintf(stderr, "error: --embree: this build has no Embree (install libembree-dev and rebuild)\n");
      return 2;
#endif
    }
  } catch (const IsaError& e) {
    std::fprintf(stderr, "error: %s%s\n", app.count("--isa") ? "--isa: " : "", e.what());
    return 2;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
