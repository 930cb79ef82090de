// pathtracer: load a scene, check the output can be written, render with the
// chosen engine, write the image (and the sample-rate image), and print the
// course renderer's end-of-render report. Errors print one line and exit 1.
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>
#include <filesystem>
#include <optional>

#include "cli_options.h"
#include "io/atomic_file.h"
#include "io/camera_setup.h"
#include "io/checkpoint.h"
#include "io/collada_loader.h"
#include "io/exr_image.h"
#include "io/image_output.h"
#include "io/scene_error.h"
#include "convergence_run.h"
#include "memory_report.h"
#include "progress_bar.h"
#include "render_engines.h"

namespace {

using namespace pt;

std::atomic<bool> g_cancel{false};
volatile sig_atomic_t g_signal = 0;

/// SIGINT / SIGTERM: ask the render to stop; a second signal kills as usual.
extern "C" void on_stop_signal(int sig) {
  g_signal = sig;
  g_cancel.store(true);
}

void install_stop_handlers() {
  struct sigaction sa {};
  sa.sa_handler = on_stop_signal;
  sa.sa_flags = SA_RESETHAND;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

/// out.png -> out.partial.png
std::filesystem::path partial_path(const std::filesystem::path& p) {
  std::filesystem::path r = p;
  r.replace_filename(p.stem().string() + ".partial" + p.extension().string());
  return r;
}

/// Saves checkpoints every `every` seconds at pass boundaries and on interrupt.
struct Checkpointing {
  std::filesystem::path path;
  std::string fingerprint;
  double every = 60.0;
  std::optional<Accumulation> resumed;
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();

  void attach(RenderControl& control) {
    if (resumed) control.resume_from = &*resumed;
    control.on_pass = [this](const Accumulation& acc) {
      auto now = std::chrono::steady_clock::now();
      if (std::chrono::duration<double>(now - last).count() < every) return;
      save_checkpoint(path, fingerprint, acc);
      last = now;
    };
    control.on_interrupt = [this](const Accumulation& acc) { save_checkpoint(path, fingerprint, acc); };
  }
};

std::filesystem::path default_output(const cli::Options& o, const Scene& scene) {
  return std::filesystem::path(scene.name).stem().string() + ".png";
}

void print_report(const cli::Options& o, const RenderOutput& out) {
  const RenderStats& st = out.stats;
  double mrays = st.seconds > 0 ? st.rays() / st.seconds / 1e6 : 0.0;
  std::string kernels = o.engine == cli::Engine::kReference
                            ? "scalar"
                            : std::string(isa_name(o.isa)) + ", " + std::to_string(isa_lanes(o.isa)) + " lanes";
  std::printf("Rendered in %.3f s with the %s engine (%s, %s); %llu rays traced (camera %llu, bounce %llu, "
              "shadow %llu); %.2f million rays per second; ",
              st.seconds, cli::engine_name(o.engine), cli::accel_name(o.accel), kernels.c_str(),
              static_cast<unsigned long long>(st.rays()), static_cast<unsigned long long>(st.camera_rays),
              static_cast<unsigned long long>(st.bounce_rays), static_cast<unsigned long long>(st.shadow_rays), mrays);
  if (st.intersection_tests > 0 || st.rays() == 0)
    std::printf("%.2f intersection tests per ray", st.rays() ? double(st.intersection_tests) / st.rays() : 0.0);
  else
    std::printf("intersection tests not counted (--count-tests)");
  std::printf("; %llu samples", static_cast<unsigned long long>(st.samples));
  if (st.invalid_samples) std::printf("; %llu invalid samples discarded", static_cast<unsigned long long>(st.invalid_samples));
  std::printf("\n");
}

/// --memory: the structures' bytes, measured after the image is written.
void print_memory(const cli::Options& o, const Scene& scene, const RenderOutput& out, const cli::EngineRunner& engine,
                  size_t queue_bytes, const std::filesystem::path& output) {
  cli::MemoryReport report;
  cli::add_scene_memory(report, scene);
  cli::EngineFootprint footprint{o.engine, cli::accel_name(o.accel), {engine.accel_bytes(), engine.accel_used_bytes()},
                                 queue_bytes};
  cli::add_render_memory(report, o.settings, scene, out, footprint, output);
  report.peak_rss_bytes = cli::peak_resident_bytes();
  std::printf("%s", cli::format_memory_report(report).c_str());
}

/// The render's camera: the scene's (or the -c file's), with -b / -d's thin
/// lens. -b without -d (or a file's focal distance) focuses on the plane
/// through the scene's centre.
Camera render_camera(const cli::Options& o, const Scene& scene) {
  const RenderSettings& rs = o.settings;
  Camera c = o.camera_file.empty() ? resolve_camera(scene, rs.width, rs.height, o.cs184_framing)
                                   : resolve_camera(read_camera_settings_file(o.camera_file), rs.width, rs.height);
  if (o.lens_radius) {
    if (!c.thin_lens() && !o.focal_distance) {
      float d = dot(scene.bounds.center() - c.position, -c.to_camera);
      c.focal_distance = std::isfinite(d) && d > 0.0f ? d : 1.0f;  // empty scene or centre behind: 1 unit
    }
    c.lens_radius = *o.lens_radius;
  }
  if (o.focal_distance) c.focal_distance = *o.focal_distance;
  return c;
}

int run(const cli::Options& o) {
  std::filesystem::path scene_path = o.scene_path.empty() ? std::filesystem::path(PT_DEFAULT_SCENE) : std::filesystem::path(o.scene_path);
  LoadResult loaded = load_collada_file(scene_path);
  if (!o.environment_map.empty()) {
    RgbImage map = read_exr(o.environment_map);
    set_environment(loaded.scene, std::make_shared<EnvironmentMap>(map.width, map.height, std::move(map.texels)));
  }
  for (const std::string& w : loaded.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!o.quiet) std::printf("%s\n", scene_summary(loaded).c_str());
  const Scene& scene = loaded.scene;
  const RenderSettings& rs = o.settings;
  if (rs.direct_by_hitting() && scene.has_delta_lights_only())
    std::fprintf(stderr,
                 "warning: %s: hemisphere sampling cannot see point or directional lights; the image will be black "
                 "(use light sampling)\n",
                 scene.name.c_str());

  if (!o.convergence_csv.empty()) {
    check_writable(o.convergence_csv);
    Camera camera = render_camera(o, scene);
    cli::EngineRunner engine(o, scene, camera);
    install_stop_handlers();
    return cli::run_convergence(o, engine, g_cancel);
  }
  std::filesystem::path output = o.output_path.empty() ? default_output(o, scene) : std::filesystem::path(o.output_path);
  check_writable(output);
  if (rs.adaptive()) check_writable(rate_image_path(output));
  if (!o.write_camera_file.empty()) check_writable(o.write_camera_file);
  if (!o.variance_file.empty()) check_writable(o.variance_file);

  Camera camera = render_camera(o, scene);

  RenderControl control;
  control.cancel = &g_cancel;
  Checkpointing checkpoint;
  if (!o.checkpoint_file.empty()) {
    checkpoint.path = o.checkpoint_file;
    checkpoint.every = o.checkpoint_every;
    checkpoint.fingerprint = render_fingerprint(cli::engine_name(o.engine), scene, camera, rs);
    check_writable(checkpoint.path);
    checkpoint.resumed = load_checkpoint(checkpoint.path, checkpoint.fingerprint, size_t(rs.width) * rs.height,
                                         static_cast<uint32_t>(rs.samples_per_pixel));
    if (checkpoint.resumed && !o.quiet)
      std::printf("Resuming from %s (%u samples per pixel done)\n", checkpoint.path.c_str(),
                  checkpoint.resumed->samples_done);
    checkpoint.attach(control);
  }
  cli::ProgressBar bar(!o.quiet);
  control.progress = [&bar](double f) { bar.update(f); };
  install_stop_handlers();
  cli::EngineRunner engine(o, scene, camera);
  size_t queue_bytes = 0;
  RenderOutput out = engine.render(rs, control, &queue_bytes);
  bar.finish();

  const PngQuantization png = o.cs184_png ? PngQuantization::kTruncate : PngQuantization::kNearest;
  if (out.cancelled) {
    std::filesystem::path partial = partial_path(output);
    write_image(partial, out.film, png);
    std::fprintf(stderr, "interrupted: wrote the image so far to %s%s\n", partial.c_str(),
                 checkpoint.path.empty() ? "" : (" and the state to " + checkpoint.path.string()).c_str());
    return 128 + (g_signal ? g_signal : SIGINT);
  }
  write_image(output, out.film, png);
  if (rs.adaptive()) write_sample_rate_image(rate_image_path(output), out.film);
  if (!o.variance_file.empty()) write_variance_image(o.variance_file, out.film);
  if (!o.write_camera_file.empty()) write_camera_settings_file(o.write_camera_file, camera, rs.width, rs.height);
  if (!checkpoint.path.empty()) std::filesystem::remove(checkpoint.path);  // complete: nothing to resume
  if (!o.quiet) {
    print_report(o, out);
    std::printf("Wrote %s%s\n", output.c_str(), rs.adaptive() ? (" and " + rate_image_path(output).string()).c_str() : "");
  }
  if (o.memory) print_memory(o, scene, out, engine, queue_bytes, output);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  pt::cli::ParseResult parsed = pt::cli::parse_command_line(argc, argv);
  if (!parsed.options) return parsed.exit_code;
  try {
    pt::set_active_isa(parsed.options->isa);
    return run(*parsed.options);
  } catch (const pt::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory\n");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
  }
  return 1;
}
