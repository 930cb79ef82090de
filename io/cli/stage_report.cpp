// print_stage_stats.
#include "stage_report.h"

#include <cstdio>

namespace pt::cli {

void print_stage_stats(const wf::StageStats& s, const RenderStats& totals) {
  double busy = 0;
  for (double t : s.seconds) busy += t;
  std::printf("stage                  thread-seconds   share\n");
  for (int i = 0; i < static_cast<int>(wf::Stage::kCount); ++i)
    std::printf("  %-20s %12.3f  %5.1f%%\n", wf::kStageNames[i], s.seconds[i], busy > 0 ? 100 * s.seconds[i] / busy : 0);
  double t_int = s.seconds[static_cast<int>(wf::Stage::kIntersect)];
  double t_sh = s.seconds[static_cast<int>(wf::Stage::kShadow)];
  std::printf("rays: camera %llu, bounce %llu (%.2f Mrays/s per thread in intersect_closest), shadow %llu "
              "(%.2f Mrays/s per thread in trace_shadow_rays)\n",
              static_cast<unsigned long long>(s.camera_rays), static_cast<unsigned long long>(s.bounce_rays),
              t_int > 0 ? (s.camera_rays + s.bounce_rays) / t_int / 1e6 : 0.0,
              static_cast<unsigned long long>(s.shadow_rays), t_sh > 0 ? s.shadow_rays / t_sh / 1e6 : 0.0);
  std::printf("paths alive per depth:");
  for (uint64_t n : s.paths_alive) std::printf(" %llu", static_cast<unsigned long long>(n));
  std::printf("\nwall %.3f s, %.2f Mrays/s overall\n", totals.seconds,
              totals.seconds > 0 ? totals.rays() / totals.seconds / 1e6 : 0.0);
}

}  // namespace pt::cli
