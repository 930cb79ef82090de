// Output files and the end report.
#include "render_outputs.h"

#include <cstdio>

#include "io/atomic_file.h"
#include "io/camera_setup.h"
#include "io/image_output.h"

namespace pt::cli {

PngQuantization png_quantization(const Options& o) {
  return o.cs184_png ? PngQuantization::kTruncate : PngQuantization::kNearest;
}

std::filesystem::path partial_path(const std::filesystem::path& p) {
  std::filesystem::path r = p;
  r.replace_filename(p.stem().string() + ".partial" + p.extension().string());
  return r;
}

void check_outputs_writable(const Options& o, const std::filesystem::path& output) {
  check_writable(output);
  if (o.settings.adaptive()) check_writable(rate_image_path(output));
  if (!o.write_camera_file.empty()) check_writable(o.write_camera_file);
  if (!o.variance_file.empty()) check_writable(o.variance_file);
  if (!o.error_image.empty()) check_writable(o.error_image);
}

void write_outputs(const Options& o, const std::filesystem::path& output, const Film& film, const Camera& camera,
                   const std::vector<float>& pixel_error) {
  const RenderSettings& rs = o.settings;
  write_image(output, film, png_quantization(o), o.exr_pixel);
  if (rs.adaptive()) write_sample_rate_image(rate_image_path(output), film);
  if (!o.variance_file.empty()) write_variance_image(o.variance_file, film);
  if (!o.error_image.empty()) write_grey_pfm(o.error_image, film.width, film.height, pixel_error);
  if (!o.write_camera_file.empty()) write_camera_settings_file(o.write_camera_file, camera, rs.width, rs.height);
}

std::string error_line(const ImageErrorEstimate& e, bool pass_based) {
  char line[160];
  if (!pass_based) return "estimated error: not available (the reference engine keeps no per-pixel sums)";
  if (!e.available) return "estimated error: not available (it needs 4 samples per pixel or more)";
  std::snprintf(line, sizeof line, "estimated error: relative RMSE %.4g, RMSE %.4g", e.relative_rmse, e.rmse);
  return line;
}

void print_report(const Options& o, const RenderStats& st, int ranks, double rank_seconds) {
  double mrays = st.seconds > 0 ? st.rays() / st.seconds / 1e6 : 0.0;
  std::string kernels = o.engine == Engine::kReference
                            ? "scalar"
                            : std::string(isa_name(o.isa)) + ", " + std::to_string(isa_lanes(o.isa)) + " lanes";
  std::string where = ranks > 1 ? " on " + std::to_string(ranks) + " MPI ranks" : "";
  std::printf(
      "Rendered in %.3f s%s with the %s engine (%s, %s); %llu rays traced (camera %llu, bounce %llu, "
      "shadow %llu); %.2f million rays per second; ",
      st.seconds, where.c_str(), engine_name(o.engine), accel_name(o.accel), kernels.c_str(),
      static_cast<unsigned long long>(st.rays()), static_cast<unsigned long long>(st.camera_rays),
      static_cast<unsigned long long>(st.bounce_rays), static_cast<unsigned long long>(st.shadow_rays), mrays);
  if (st.intersection_tests > 0 || st.rays() == 0)
    std::printf("%.2f intersection tests per ray", st.rays() ? double(st.intersection_tests) / st.rays() : 0.0);
  else std::printf("intersection tests not counted (--count-tests)");
  std::printf("; %llu samples", static_cast<unsigned long long>(st.samples));
  if (st.invalid_samples)
    std::printf("; %llu invalid samples discarded", static_cast<unsigned long long>(st.invalid_samples));
  if (ranks > 1) std::printf("; the ranks were busy %.3f s summed", rank_seconds);
  std::printf("\n");
}

}  // namespace pt::cli
