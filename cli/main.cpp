// pathtracer: load a scene, check the output can be written, render with the
// chosen engine, write the image (and the sample-rate image), and print the
// course renderer's end-of-render report. Errors print one line and exit 1.
#include <signal.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "cli_options.h"
#include "io/atomic_file.h"
#include "io/camera_setup.h"
#include "io/checkpoint.h"
#include "io/collada_loader.h"
#include "io/exr_image.h"
#include "io/image_output.h"
#include "io/scene_export.h"
#if PT_WITH_LIVE
#include "live_command.h"
#endif
#include "io/tile_set.h"
#include "io/scene_error.h"
#include "convergence_run.h"
#include "early_stop.h"
#include "memory_report.h"
#include "distributed/mpi_job.h"
#include "progress_bar.h"
#include "render_camera.h"
#include "render_engines.h"
#include "render_outputs.h"
#include "shard_merge.h"
#if PT_WITH_MPI
#include "distributed/mpi_render.h"
#endif

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

/// Saves checkpoints every `every` seconds at pass boundaries and on interrupt.
struct Checkpointing {
  std::filesystem::path path;
  std::string fingerprint;
  double every = 60.0;
  std::optional<Accumulation> resumed;
  std::chrono::steady_clock::time_point last = std::chrono::steady_clock::now();

  /// Whether `every` seconds have passed since the last save (then counts one from now).
  bool due() {
    auto now = std::chrono::steady_clock::now();
    if (path.empty() || std::chrono::duration<double>(now - last).count() < every) return false;
    last = now;
    return true;
  }

  void attach(RenderControl& control) {
    if (resumed) control.resume_from = &*resumed;
    control.on_pass = [this](const Accumulation& acc) {
      if (due()) save_checkpoint(path, fingerprint, acc);
    };
    control.on_interrupt = [this](const Accumulation& acc) { save_checkpoint(path, fingerprint, acc); };
  }
};

/// The test hook PT_TEST_SIGINT_AFTER_PASS=N: the process sends itself SIGINT
/// after its N-th completed pass, so that tests stop a render at a known point
/// on any machine (the stop handler, the partial image, the checkpoint) instead
/// of signalling it after a guessed delay. Unset, or not a positive number: no hook.
void add_test_interrupt_hook(RenderControl& control) {
  const char* value = std::getenv("PT_TEST_SIGINT_AFTER_PASS");
  const long after = value ? std::strtol(value, nullptr, 10) : 0;
  if (after <= 0) return;
  control.on_pass = [inner = std::move(control.on_pass), after, passes = 0L](const Accumulation& acc) mutable {
    if (inner) inner(acc);
    if (++passes == after) raise(SIGINT);
  };
}

/// The test hook PT_TEST_SECONDS_PER_SAMPLE=S: --time reads a clock on which
/// every sample per pixel takes S seconds, so that tests know where --time
/// stops on any machine. Unset, or not a positive number: the real clock.
cli::EarlyStop::Clock test_clock() {
  const char* value = std::getenv("PT_TEST_SECONDS_PER_SAMPLE");
  const double per_sample = value ? std::strtod(value, nullptr) : 0.0;
  if (!(per_sample > 0.0)) return {};
  return [per_sample](const Accumulation& acc) { return per_sample * acc.samples_done; };
}

std::filesystem::path default_output(const cli::Options& o, const Scene& scene) {
  return std::filesystem::path(scene.name).stem().string() + ".png";
}

/// --memory: the structures' bytes, measured after the image is written.
void print_memory(const cli::Options& o, const Scene& scene, const RenderOutput& out, const cli::EngineRunner& engine,
                  const cli::EngineRunner::QueueBytes& queues, const std::filesystem::path& output) {
  cli::MemoryReport report;
  cli::add_scene_memory(report, scene);
  cli::EngineFootprint footprint{o.engine,
                                 cli::accel_name(o.accel),
                                 {engine.accel_bytes(), engine.accel_used_bytes()},
                                 queues.queues,
                                 queues.tracer};
  cli::add_render_memory(report, o.settings, scene, out, footprint, output);
  report.peak_rss_bytes = cli::peak_resident_bytes();
  std::printf("%s", cli::format_memory_report(report).c_str());
}

/// Everything a render needs before it starts; loading, checks and the
/// BVH build throw InputError (or bad_alloc) and are done by every rank.
struct Prepared {
  LoadResult loaded;
  Camera camera;
  std::filesystem::path output;
  std::unique_ptr<cli::EngineRunner> engine;
  Checkpointing checkpoint;      ///< one process: the pass-based engines' state
  std::optional<TileSet> tiles;  ///< tiles (--shard, mpirun): the header and a checkpoint's tiles
};

void prepare(const cli::Options& o, const dist::MpiJob& job, Prepared& p) {
  const bool speaks = job.rank() == 0 && !o.quiet;
  std::filesystem::path scene_path =
      o.scene_path.empty() ? std::filesystem::path(PT_DEFAULT_SCENE) : std::filesystem::path(o.scene_path);
  p.loaded = load_collada_file(scene_path);
  if (!o.environment_map.empty()) {
    RgbImage map = read_exr(o.environment_map);
    set_environment(p.loaded.scene, std::make_shared<EnvironmentMap>(map.width, map.height, std::move(map.texels)));
  }
  const Scene& scene = p.loaded.scene;
  const RenderSettings& rs = o.settings;
  if (job.rank() == 0) {
    for (const std::string& w : p.loaded.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
    if (rs.direct_by_hitting() && scene.has_delta_lights_only())
      std::fprintf(stderr,
                   "warning: %s: hemisphere sampling cannot see point or directional lights; the image will be black "
                   "(use light sampling)\n",
                   scene.name.c_str());
  }
  if (speaks) std::printf("%s\n", scene_summary(p.loaded).c_str());
  const bool tiled = o.shard_count > 0 || job.size() > 1;
  if (tiled && (o.stops_early() || !o.error_image.empty()))
    throw InputError(std::string(o.target_error > 0.0 ? "--target-error"
                                 : o.time_limit > 0.0 ? "--time"
                                                      : "--error-image") +
                     " needs the whole image in one process; not with --shard or mpirun");
  if (tiled && (o.stats || o.memory || !o.convergence_csv.empty()))
    throw InputError(std::string(o.stats    ? "--stats"
                                 : o.memory ? "--memory"
                                            : "--convergence-csv") +
                     " reports one whole-image render in one process; not with --shard or mpirun");
  if (!o.convergence_csv.empty()) {
    check_writable(o.convergence_csv);
  } else {
    p.output = !o.output_path.empty() ? std::filesystem::path(o.output_path)
               : o.shard_count > 0    ? std::filesystem::path(std::filesystem::path(scene.name).stem().string() + "." +
                                                              std::to_string(o.shard_index) + "-of-" +
                                                              std::to_string(o.shard_count) + ".tiles")
                                      : default_output(o, scene);
    if (job.rank() != 0) {
      // only rank 0 writes
    } else if (o.shard_count > 0) {
      check_writable(p.output);
    } else {
      cli::check_outputs_writable(o, p.output);
    }
  }
  p.camera = cli::render_camera(o, scene);
  if (tiled) p.tiles = TileSet{cli::tile_set_header(o, scene, p.camera), {}, {}};
  if (!o.checkpoint_file.empty() && job.rank() == 0 && o.convergence_csv.empty()) {
    p.checkpoint.path = o.checkpoint_file;
    p.checkpoint.every = o.checkpoint_every;
    check_writable(p.checkpoint.path);
    if (p.tiles) {
      std::error_code ec;
      if (std::filesystem::exists(p.checkpoint.path, ec)) {
        TileSet saved = load_tile_set(p.checkpoint.path);
        if (!(saved.header == p.tiles->header))
          throw InputError(p.checkpoint.path.string() + ": checkpoint was written for a different render (" +
                           saved.header.fingerprint.substr(0, 120) + "...)");
        p.tiles->tiles = std::move(saved.tiles);
        if (speaks)
          std::printf("Resuming from %s (%zu of %u tiles done)\n", p.checkpoint.path.c_str(), p.tiles->tiles.size(),
                      p.tiles->header.grid().count());
      }
    } else {
      p.checkpoint.fingerprint = render_fingerprint(cli::engine_name(o.engine), scene, p.camera, rs);
      p.checkpoint.resumed =
          load_checkpoint(p.checkpoint.path, p.checkpoint.fingerprint, size_t(rs.area().width) * rs.area().height,
                          static_cast<uint32_t>(rs.samples_per_pixel));
      if (p.checkpoint.resumed && speaks)
        std::printf("Resuming from %s (%u samples per pixel done)\n", p.checkpoint.path.c_str(),
                    p.checkpoint.resumed->samples_done);
    }
  }
  install_stop_handlers();  // from here on a stop ends the render cleanly, during the BVH build too
  p.engine = std::make_unique<cli::EngineRunner>(o, scene, p.camera);
}

/// One process renders the whole image with the engine's own passes.
int render_in_one_process(const cli::Options& o, Prepared& p) {
  const RenderSettings& rs = o.settings;
  RenderControl control;
  control.cancel = &g_cancel;
  if (!p.checkpoint.path.empty()) p.checkpoint.attach(control);
  add_test_interrupt_hook(control);
  cli::ProgressBar bar(!o.quiet);
  control.progress = [&bar](double f) { bar.update(f); };
  control.pixel_error = !o.error_image.empty();
  cli::EarlyStop early_stop(o.target_error, o.time_limit, test_clock());
  if (o.stops_early()) control.stop_at_power_of_two = early_stop.rule();
  cli::EngineRunner::QueueBytes queues;
  RenderOutput out = p.engine->render(rs, control, &queues);
  bar.finish();

  if (out.cancelled) {
    std::filesystem::path partial = cli::partial_path(p.output);
    write_image(partial, out.film, cli::png_quantization(o), o.exr_pixel);
    std::fprintf(stderr, "interrupted: wrote the image so far to %s%s\n", partial.c_str(),
                 p.checkpoint.path.empty() ? "" : (" and the state to " + p.checkpoint.path.string()).c_str());
    return 128 + (g_signal ? g_signal : SIGINT);
  }
  cli::write_outputs(o, p.output, out.film, p.camera, out.pixel_error);
  if (!p.checkpoint.path.empty()) std::filesystem::remove(p.checkpoint.path);  // complete: nothing to resume
  const uint32_t max_samples = static_cast<uint32_t>(rs.samples_per_pixel);
  if (std::string warning = early_stop.missed_target_warning(out, max_samples); !warning.empty())
    std::fprintf(stderr, "%s\n", warning.c_str());
  if (!o.quiet) {
    if (o.stops_early()) std::printf("%s\n", early_stop.stop_line(out).c_str());
    cli::print_report(o, out.stats);
    std::printf("%s\n", cli::error_line(out.error, p.engine->pass_based()).c_str());
    std::printf("Wrote %s%s\n", p.output.c_str(),
                rs.adaptive() ? (" and " + rate_image_path(p.output).string()).c_str() : "");
  }
  if (o.memory) print_memory(o, p.loaded.scene, out, *p.engine, queues, p.output);
  return 0;
}

#if PT_WITH_MPI
/// mpirun: the ranks share the tiles (distributed/mpi_render.h); rank 0 writes the
/// outputs, checkpoints and, when stopped, the partial image.
int render_across_ranks(const cli::Options& o, const dist::MpiJob& job, Prepared& p) {
  TileSet& set = *p.tiles;
  const TileGrid grid = set.header.grid();
  cli::ProgressBar bar(job.rank() == 0 && !o.quiet);
  auto after_tile = [&](const TileSet& s) {
    bar.update(double(s.tiles.size()) / grid.count());
    if (p.checkpoint.due()) save_tile_set(p.checkpoint.path, s);
  };
  const size_t resumed = set.tiles.size();
  dist::TileWork work{cli::region_renderer(*p.engine), o.settings, grid, &g_cancel};
  auto start = std::chrono::steady_clock::now();
  bool finished = dist::render_across_ranks(job, work, set, after_tile);
  if (job.rank() != 0) return 0;
  bar.finish();
  RenderStats stats = set.stats;
  stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  Film film(set.header.width, set.header.height, set.header.max_samples);
  for (const TilePixels& t : set.tiles) paste_tile(film, grid, t);
  if (!finished) {
    // Stopped: save what is done and end at once (mpirun kills every rank a
    // second after it forwards a stop, and this rank must not wait in
    // MPI_Finalize for ranks that are gone).
    std::filesystem::path partial = cli::partial_path(p.output);
    if (!p.checkpoint.path.empty()) save_tile_set(p.checkpoint.path, set);
    write_image(partial, film, cli::png_quantization(o), o.exr_pixel);
    std::fprintf(stderr, "interrupted: wrote the %zu of %u tiles finished to %s%s\n", set.tiles.size(), grid.count(),
                 partial.c_str(),
                 p.checkpoint.path.empty() ? "" : (" and to the checkpoint " + p.checkpoint.path.string()).c_str());
    std::fflush(nullptr);
    std::_Exit(128 + (g_signal ? g_signal : SIGINT));
  }
  cli::write_outputs(o, p.output, film, p.camera);
  if (!p.checkpoint.path.empty()) std::filesystem::remove(p.checkpoint.path);
  if (!o.quiet) {
    cli::print_report(o, stats, job.size(), set.stats.seconds);
    std::printf("estimated error: not available (tiles keep no per-pixel sums across ranks)\n");
    if (resumed) std::printf("Resumed %zu of %u tiles from %s\n", resumed, grid.count(), p.checkpoint.path.c_str());
    std::printf("Wrote %s%s\n", p.output.c_str(),
                o.settings.adaptive() ? (" and " + rate_image_path(p.output).string()).c_str() : "");
  }
  return 0;
}
#endif

/// The message of the exception being handled, as main prints it.
std::string current_error() {
  try {
    throw;
  } catch (const std::bad_alloc&) { return "out of memory"; } catch (const std::exception& e) {
    return e.what();
  } catch (...) { return "unknown error"; }
}

/// --export-scene: the loaded scene and the render's camera as JSON; no render.
int export_scene(const cli::Options& o) {
  check_writable(o.export_scene);
  LoadResult loaded = load_collada_file(o.scene_path.empty() ? std::filesystem::path(PT_DEFAULT_SCENE)
                                                             : std::filesystem::path(o.scene_path));
  for (const std::string& w : loaded.warnings) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (!o.environment_map.empty()) {
    RgbImage map = read_exr(o.environment_map);
    set_environment(loaded.scene, std::make_shared<EnvironmentMap>(map.width, map.height, std::move(map.texels)));
  }
  const Camera camera = cli::render_camera(o, loaded.scene);
  write_file_atomically(o.export_scene, scene_to_json(loaded.scene, camera, o.settings.width, o.settings.height));
  if (!o.quiet) std::printf("Wrote %s\n", o.export_scene.c_str());
  return 0;
}

/// --scene-info: what the loader made of the file and what it ignored; no render.
int print_scene_info(const cli::Options& o) {
  LoadResult loaded = load_collada_file(o.scene_path.empty() ? std::filesystem::path(PT_DEFAULT_SCENE)
                                                             : std::filesystem::path(o.scene_path));
  std::fputs(scene_info(loaded).c_str(), stdout);
  return 0;
}

int run(const cli::Options& o, const dist::MpiJob& job) {
  if (!o.merge.empty()) return job.rank() == 0 ? cli::run_merge(o) : 0;
  if (o.scene_info) return job.rank() == 0 ? print_scene_info(o) : 0;
  if (!o.export_scene.empty()) return job.rank() == 0 ? export_scene(o) : 0;
  if (o.serve_port >= 0) {
#if PT_WITH_LIVE
    if (job.size() > 1) throw InputError("--serve runs in one process, not under mpirun");
    install_stop_handlers();
    return cli::run_live_view(o, g_cancel);
#else
    throw InputError("--serve: this build has no live view (install libmicrohttpd-dev and build again)");
#endif
  }
  Prepared p;
  if (job.size() == 1) {
    prepare(o, job, p);
  } else {
    // Every rank prepares; if one fails, all stop together (none may wait for
    // it), and a failure every rank shares is reported once, by rank 0.
    std::string error;
    try {
      prepare(o, job, p);
    } catch (...) { error = current_error(); }
    dist::MpiJob::Readiness ready = job.agree_ready(error.empty());
    if (!ready.all) {
      if (!error.empty() && job.rank() == 0) std::fprintf(stderr, "error: %s\n", error.c_str());
      else if (!error.empty() && ready.rank0)
        std::fprintf(stderr, "error: rank %d of %d: %s\n", job.rank(), job.size(), error.c_str());
      return 1;
    }
  }
  if (!o.convergence_csv.empty()) return cli::run_convergence(o, *p.engine, g_cancel);
  if (o.shard_count > 0 && job.rank() != 0) return 0;  // a shard is one process's work
  if (o.shard_count > 0)
    return cli::run_shard(o, p.loaded.scene, p.camera, *p.engine, p.output, g_cancel)
               ? 0
               : 128 + (g_signal ? g_signal : SIGINT);
#if PT_WITH_MPI
  if (job.size() > 1) return render_across_ranks(o, job, p);
#endif
  return render_in_one_process(o, p);
}

/// Ranks other than 0 keep quiet while the command line is parsed (every
/// rank parses the same line; rank 0 reports its errors once).
cli::ParseResult parse_quietly_unless_rank0(int argc, char** argv, const dist::MpiJob& job) {
  if (job.rank() == 0) return cli::parse_command_line(argc, argv);
  std::ostringstream sink;
  std::streambuf* out = std::cout.rdbuf(sink.rdbuf());
  std::streambuf* err = std::cerr.rdbuf(sink.rdbuf());
  cli::ParseResult parsed = cli::parse_command_line(argc, argv);
  std::cout.rdbuf(out);
  std::cerr.rdbuf(err);
  return parsed;
}

}  // namespace

int main(int argc, char** argv) {
  pt::dist::MpiJob job(&argc, &argv);
  pt::cli::ParseResult parsed = parse_quietly_unless_rank0(argc, argv, job);
  if (!parsed.options) return parsed.exit_code;
  try {
    pt::set_active_isa(parsed.options->isa);
    return run(*parsed.options, job);
  } catch (...) {
    std::string error = current_error();
    if (job.rank() == 0) std::fprintf(stderr, "error: %s\n", error.c_str());
    else std::fprintf(stderr, "error: rank %d of %d: %s\n", job.rank(), job.size(), error.c_str());
    if (job.size() > 1) job.abort(1);  // the other ranks may be waiting for this one
  }
  return 1;
}
