// print_stage_stats.
#include "stage_report.h"

#include <cstdio>
#include <string>

namespace pt::cli {
namespace {

double seconds_of(const wf::StageStats& s, wf::Stage stage) { return s.seconds[static_cast<int>(stage)]; }

void rate_line(const char* what, uint64_t rays, double seconds) {
  std::printf("  %-34s %12llu rays %8.2f Mrays/s per thread\n", what, static_cast<unsigned long long>(rays),
              seconds > 0 ? rays / seconds / 1e6 : 0.0);
}

}  // namespace

void print_stage_stats(const wf::StageStats& s, const RenderStats& totals, Isa isa) {
  double busy = 0;
  for (double t : s.seconds) busy += t;
  std::printf("kernels: %s, %zu lanes\n", std::string(isa_name(isa)).c_str(), isa_lanes(isa));
  std::printf("stage                             thread-seconds   share\n");
  for (int i = 0; i < static_cast<int>(wf::Stage::kCount); ++i)
    std::printf("  %-30s %12.3f  %5.1f%%\n", wf::kStageNames[i], s.seconds[i],
                busy > 0 ? 100 * s.seconds[i] / busy : 0);
  using wf::Stage;
  std::printf("ray throughput inside the render (stage time per ray):\n");
  rate_line("camera rays", s.camera_rays, seconds_of(s, Stage::kIntersectCamera));
  rate_line("bounce rays", s.bounce_rays, seconds_of(s, Stage::kIntersectBounce));
  rate_line("shadow rays from first hits", s.first_hit_shadow_rays, seconds_of(s, Stage::kShadowFirstHit));
  rate_line("later shadow rays", s.shadow_rays - s.first_hit_shadow_rays, seconds_of(s, Stage::kShadowLater));
  std::printf("tracer time per kind of queue (the queue tracer, or --trace single):\n");
  std::printf("  %-34s %8s %12s %12s %10s\n", "queue", "queues", "rays/queue", "us/queue", "Mrays/s");
  for (int k = 0; k < static_cast<int>(wf::TracedQueue::kCount); ++k) {
    const wf::QueueTiming& q = s.traced[k];
    if (q.queues == 0) continue;
    std::printf("  %-34s %8llu %12.1f %12.1f %10.2f\n", wf::kTracedQueueNames[k],
                static_cast<unsigned long long>(q.queues), double(q.rays) / q.queues, 1e6 * q.seconds / q.queues,
                q.seconds > 0 ? q.rays / q.seconds / 1e6 : 0.0);
  }
  std::printf("paths alive per depth:");
  for (uint64_t n : s.paths_alive) std::printf(" %llu", static_cast<unsigned long long>(n));
  std::printf("\nwall %.3f s, %.2f Mrays/s overall\n", totals.seconds,
              totals.seconds > 0 ? totals.rays() / totals.seconds / 1e6 : 0.0);
}

void print_bvh4_stats(const Bvh4BuildStats& b) {
  std::printf(
      "bvh4: %u triangles, %u build references, %u nodes, %u leaves, %u blocks, %d levels, %.1f bytes per "
      "triangle, built in %.1f ms\n",
      b.triangles, b.references, b.nodes, b.leaves, b.blocks, b.depth, b.bytes_per_triangle, b.build_ms);
}

}  // namespace pt::cli
