// run_convergence.
#include "convergence_run.h"

#include <cstdio>
#include <sstream>

#include "io/atomic_file.h"
#include "io/image_metrics.h"
#include "io/image_output.h"
#include "io/scene_error.h"

namespace pt::cli {

int run_convergence(const Options& o, const EngineRunner& engine, const std::atomic<bool>& cancel) {
  int ref_w = 0, ref_h = 0;
  std::vector<float3> reference = read_pfm(o.reference_image, ref_w, ref_h);
  if (ref_w != o.settings.width || ref_h != o.settings.height)
    throw InputError(o.reference_image + ": reference is " + std::to_string(ref_w) + "x" + std::to_string(ref_h) +
                     " but the render is " + std::to_string(o.settings.width) + "x" +
                     std::to_string(o.settings.height));
  std::ostringstream csv;
  csv << "method,spp,seconds,rays,rmse,rel_mse,mean_bias,est_rmse,est_rel_rmse\n";
  RenderSettings rs = o.settings;
  Accumulation acc;
  bool resumable = false;
  double seconds = engine.build_seconds();
  uint64_t rays = 0;
  const int max_spp = o.settings.samples_per_pixel;
  for (int spp = 1;; spp = std::min(spp * 2, max_spp)) {
    rs.samples_per_pixel = spp;
    RenderControl control;
    control.cancel = &cancel;
    if (engine.pass_based() && !o.convergence_restart) {
      if (resumable) control.resume_from = &acc;
      control.on_pass = [&](const Accumulation& a) {
        acc = a;
        resumable = true;
      };
    }
    RenderOutput out = engine.render(rs, control);
    if (out.cancelled) break;
    if (engine.pass_based() && !o.convergence_restart) {
      seconds += out.stats.seconds;
      rays += out.stats.rays();
    } else {  // a render from the start: its own time and rays
      seconds = engine.build_seconds() + out.stats.seconds;
      rays = out.stats.rays();
    }
    ErrorMetrics m = compare_images(out.film.radiance, reference);
    // The render's own estimate (empty fields where it has none: the reference
    // engine, fewer than 4 samples per pixel).
    char estimate[64] = ",";
    if (out.error.available)
      std::snprintf(estimate, sizeof estimate, "%.9g,%.9g", out.error.rmse, out.error.relative_rmse);
    char row[320];
    std::snprintf(row, sizeof row, "%s,%d,%.6f,%llu,%.9g,%.9g,%.9g,%s\n", o.label.c_str(), spp, seconds,
                  static_cast<unsigned long long>(rays), m.rmse, m.rel_mse, m.mean_bias, estimate);
    csv << row;
    if (!o.quiet) std::printf("%s", row);
    if (spp == max_spp) break;
  }
  write_file_atomically(o.convergence_csv, csv.str());
  return cancel.load() ? 130 : 0;
}

}  // namespace pt::cli
