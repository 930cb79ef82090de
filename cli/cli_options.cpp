// parse_command_line on CLI11. CLI11 only splits the command line: every
// value is kept as text and converted by option_values.h, so each bad value
// gets the same kind of one-line message (flag, meaning, accepted range, text
// given); validate() then checks values against each other.
#include "cli_options.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <thread>
#include <type_traits>

#include <CLI/CLI.hpp>

#include "io/tile_set.h"
#include "option_values.h"

namespace pt::cli {
namespace {

constexpr int kMaxDimension = 16384;
constexpr int64_t kMaxPixels = int64_t(1) << 27;
constexpr int kStopEarlyMaxSamples = 1 << 16;  ///< -s when --target-error or --time come without it
constexpr std::array<const char*, 3> kEngines = {"reference", "wavefront", "megakernel"};  // order of Engine
constexpr std::array<const char*, 3> kAccels = {"bvh4", "bvh2", "none"};                   // order of AccelChoice
constexpr std::array<const char*, 4> kBounceModes = {"accumulate", "only-m", "direct", "indirect"};
constexpr std::array<const char*, 4> kDirectModes = {"light", "hemisphere", "cosine", "mis"};  // DirectLighting
constexpr std::array<const char*, 2> kSamplers = {"independent", "sobol"};                     // PixelSampler
constexpr std::array<const char*, 2> kTraceModes = {"queue", "single"};                        // wf::TraceMode
constexpr std::array<const char*, 2> kRouletteModes = {"fixed", "throughput"};                 // RouletteMode
constexpr std::array<const char*, 2> kExrPixels = {"float", "half"};                           // ExrPixel

/// Every valued flag as typed; converted after CLI11 has split the line.
struct RawValues {
  std::string samples, light_samples, threads, max_depth, leaf_size, seed, rr, checkpoint_every, presplit;
  std::string engine, bvh, bounces, direct, sampler, rr_mode, isa, lens_radius, focal_distance, tile, shard, trace;
  std::string exr_pixel, target_error, time_limit;
  std::vector<std::string> resolution, adaptive, region;
  bool hemisphere = false, normals = false, cs184 = false, list_isa = false, serve = false;
  std::optional<std::string> serve_port;  ///< the PORT after --serve, if one was given
};

/// Converts the raw values that were given into `o`, keeping the first error.
class Converter {
 public:
  Converter(const CLI::App& app, Options& o) : app_(app), o_(o) {}

  template <class T>
  void integer(const char* flag, const char* what, const std::string& text, int64_t lo, int64_t hi, T& out) {
    int64_t v = 0;
    if (error.empty() && app_.count(flag) > 0 && (error = parse_integer(flag, what, text, lo, hi, v)).empty())
      out = static_cast<T>(v);
  }
  template <class T>
  void number(const char* flag, const char* what, const std::string& text, const char* range, bool (*accept)(double),
              T& out) {
    double v = 0.0;
    if (error.empty() && app_.count(flag) > 0 && (error = parse_number(flag, what, text, range, accept, v)).empty())
      out = static_cast<T>(v);
  }
  template <class E, size_t N>
  void choice(const char* flag, const char* what, const std::string& text, const std::array<const char*, N>& names,
              E& out) {
    size_t i = 0;
    if (error.empty() && app_.count(flag) > 0 && (error = parse_choice(flag, what, text, names, i)).empty())
      out = static_cast<E>(i);
  }

  void convert(const RawValues& raw);
  std::string error;

 private:
  const CLI::App& app_;
  Options& o_;
};

void Converter::convert(const RawValues& raw) {
  RenderSettings& s = o_.settings;
  integer("-s", "samples per pixel", raw.samples, 1, 1 << 24, s.samples_per_pixel);
  integer("-l", "light samples", raw.light_samples, 1, 4096, s.light_samples);
  integer("-t", "thread count", raw.threads, 1, 1024, s.threads);
  integer("-m", "maximum depth", raw.max_depth, 0, 1024, s.max_depth);
  integer("-r", "width", raw.resolution.empty() ? "" : raw.resolution[0], 1, kMaxDimension, s.width);
  integer("-r", "height", raw.resolution.empty() ? "" : raw.resolution[1], 1, kMaxDimension, s.height);
  integer("-a", "batch size", raw.adaptive.empty() ? "" : raw.adaptive[0], 1, 1 << 24, s.adaptive_batch);
  number(
      "-a", "tolerance", raw.adaptive.empty() ? "" : raw.adaptive[1], "a number >= 0 (0 turns adaptive sampling off)",
      [](double v) { return v >= 0.0 && v <= std::numeric_limits<float>::max(); }, s.adaptive_tolerance);
  if (app_.count("-p") > 0) {
    Region r;
    const char* names[4] = {"region x", "region y", "region width", "region height"};
    int* fields[4] = {&r.x, &r.y, &r.width, &r.height};
    for (int i = 0; i < 4; ++i) integer("-p", names[i], raw.region[i], i < 2 ? 0 : 1, kMaxDimension, *fields[i]);
    s.region = r;
  }
  number(
      "--rr", "continuation probability", raw.rr, "a number in (0, 1]", [](double v) { return v > 0.0 && v <= 1.0; },
      s.rr_continue);
  integer("--seed", "seed", raw.seed, 0, std::numeric_limits<uint32_t>::max(), s.seed);
  auto finite_at_least_zero = [](double v) { return v >= 0.0 && v <= 1e30; };
  auto positive = [](double v) { return v > 0.0 && v <= 1e30; };
  float lens_radius = -1.0f, focal_distance = -1.0f;
  number("-b", "lens radius", raw.lens_radius, "a number >= 0 (0: pinhole)", finite_at_least_zero, lens_radius);
  number("-d", "focal distance", raw.focal_distance, "a positive number", positive, focal_distance);
  if (app_.count("-b") > 0 && error.empty()) o_.lens_radius = lens_radius;
  if (app_.count("-d") > 0 && error.empty()) o_.focal_distance = focal_distance;
  integer("--leaf-size", "leaf size", raw.leaf_size, 1, 64, o_.max_leaf_size);
  number(
      "--presplit", "pre-splitting budget", raw.presplit, "a number from 0 to 16 (extra references per triangle)",
      [](double v) { return v >= 0.0 && v <= 16.0; }, o_.presplit_budget);
  integer("--tile", "tile size", raw.tile, 1, pt::kMaxTileSize, o_.tile_size);
  if (app_.count("--shard") > 0 && error.empty()) {
    size_t slash = raw.shard.find('/');
    if (slash == std::string::npos) {
      error = "--shard: expected I/N (this job's share I of N, counted from 0), got \"" + raw.shard + "\"";
    } else {
      integer("--shard", "shard count N of I/N", raw.shard.substr(slash + 1), 1, 1 << 20, o_.shard_count);
      integer("--shard", "shard index I of I/N", raw.shard.substr(0, slash), 0, std::max(0, o_.shard_count - 1),
              o_.shard_index);
    }
  }
  number(
      "--target-error", "target relative RMSE", raw.target_error, "a positive number (e.g. 0.01 for 1%)",
      [](double v) { return v > 0.0 && v <= 1e30; }, o_.target_error);
  number(
      "--time", "time limit", raw.time_limit, "a positive number of seconds",
      [](double v) { return v > 0.0 && v <= 1e9; }, o_.time_limit);
  if (o_.stops_early() && app_.count("-s") == 0) s.samples_per_pixel = kStopEarlyMaxSamples;
  number(
      "--checkpoint-every", "checkpoint interval", raw.checkpoint_every, "a positive number of seconds",
      [](double v) { return v > 0.0; }, o_.checkpoint_every);
  choice("--engine", "engine", raw.engine, kEngines, o_.engine);
  if (o_.engine == Engine::kReference) o_.accel = AccelChoice::kBvh2;  // its default
  choice("--bvh", "acceleration structure", raw.bvh, kAccels, o_.accel);
  choice("--bounces", "bounce mode", raw.bounces, kBounceModes, s.bounces);
  choice("--direct", "direct light estimator", raw.direct, kDirectModes, s.direct);
  choice("--sampler", "sampler", raw.sampler, kSamplers, s.sampler);
  choice("--exr-pixel", "EXR pixel type", raw.exr_pixel, kExrPixels, o_.exr_pixel);
  choice("--rr-mode", "Russian roulette mode", raw.rr_mode, kRouletteModes, s.roulette);
  choice("--trace", "trace mode", raw.trace, kTraceModes, o_.trace);
  if (error.empty()) {  // the level in use: --isa, else the environment's PT_ISA, else the widest
    try {
      o_.isa = app_.count("--isa") > 0 ? resolve_isa(raw.isa) : active_isa();
    } catch (const IsaError& e) { error = (app_.count("--isa") > 0 ? "--isa: " : "") + std::string(e.what()); }
  }
  if (raw.serve) {
    o_.serve_port = 8184;
    if (error.empty() && raw.serve_port) {
      int64_t port = 0;
      if ((error = parse_integer("--serve", "port", *raw.serve_port, 0, 65535, port)).empty())
        o_.serve_port = int(port);
    }
    if (app_.count("-s") == 0) s.samples_per_pixel = 1024;  // the live view accumulates until this many
    if (app_.count("-t") == 0) s.threads = int(std::max(1u, std::thread::hardware_concurrency()));
  } else if (app_.count("--bind") > 0 && error.empty()) {
    error = "--bind goes with --serve";
  }
  if (raw.hemisphere) {
    if (error.empty() && app_.count("--direct") > 0 && s.direct != DirectLighting::kHemisphere)
      error = "-H and --direct " + raw.direct + " contradict each other";
    s.direct = DirectLighting::kHemisphere;
  }
}

/// --serve: the flags that describe one render to a file, which the live view does not make.
std::string validate_live(const Options& o) {
  const RenderSettings& s = o.settings;
  if (o.engine != Engine::kWavefront || o.accel != AccelChoice::kBvh4)
    return "--serve: the live view renders with the wavefront engine and the BVH4 (no --engine or --bvh)";
  const char* alone = !o.merge.empty()                   ? "--merge"
                      : !o.export_scene.empty()          ? "--export-scene"
                      : o.scene_info                     ? "--scene-info"
                      : o.shard_count > 0                ? "--shard"
                      : !o.checkpoint_file.empty()       ? "--checkpoint"
                      : !o.convergence_csv.empty()       ? "--convergence-csv"
                      : !o.variance_file.empty()         ? "--variance"
                      : !o.error_image.empty()           ? "--error-image"
                      : o.target_error > 0.0             ? "--target-error"
                      : o.time_limit > 0.0               ? "--time"
                      : s.region                         ? "-p"
                      : o.stats                          ? "--stats"
                      : o.memory                         ? "--memory"
                      : o.trace != wf::TraceMode::kQueue ? "--trace"
                      : !o.dump_queues.empty()           ? "--dump-queues"
                      : o.queue_order_shading            ? "--shade-in-queue-order"
                      : o.count_tests                    ? "--count-tests"
                                                         : nullptr;
  if (alone) return std::string("--serve: ") + alone + " is for renders to a file, not the live view";
  if (s.width < 16 || s.height < 16 || s.width > 4096 || s.height > 4096 ||
      int64_t(s.width) * s.height > (int64_t(1) << 22))
    return "--serve: -r " + std::to_string(s.width) + " " + std::to_string(s.height) +
           ": the live view takes 16 to 4096 pixels a side and at most 4194304 pixels";
  if (o.bind_address.empty() || o.bind_address.size() > 253 ||
      o.bind_address.find_first_of(" \t\r\n/") != std::string::npos)
    return "--bind: expected an address such as 127.0.0.1, ::1 or 0.0.0.0, got \"" + o.bind_address + "\"";
  return {};
}

/// Returns an error message, or empty if the converted options are consistent.
std::string validate(const Options& o) {
  const RenderSettings& s = o.settings;
  if (int64_t(s.width) * s.height > kMaxPixels)
    return "-r: " + std::to_string(s.width) + " x " + std::to_string(s.height) + " is more than " +
           std::to_string(kMaxPixels) + " pixels";
  if (s.region) {
    const Region& r = *s.region;
    if (int64_t(r.x) + r.width > s.width || int64_t(r.y) + r.height > s.height)
      return "-p: region " + std::to_string(r.x) + " " + std::to_string(r.y) + " " + std::to_string(r.width) + " " +
             std::to_string(r.height) + " is not inside the " + std::to_string(s.width) + "x" +
             std::to_string(s.height) + " image";
  }
  std::error_code ec;
  if (!o.output_path.empty() && !o.scene_path.empty() && std::filesystem::equivalent(o.output_path, o.scene_path, ec))
    return "-f: the output " + o.output_path + " would overwrite the scene file";
  if (o.reference_image.empty() != o.convergence_csv.empty()) return "--reference and --convergence-csv go together";
  if (o.convergence_restart && o.convergence_csv.empty()) return "--convergence-restart needs --convergence-csv";
  if (o.label.empty() || o.label.find_first_of(",\"\n\r") != std::string::npos)
    return "--label: must be non-empty without commas, quotes or line breaks (it is a CSV field)";
  if (o.engine == Engine::kReference && o.accel == AccelChoice::kBvh4)
    return "--bvh bvh4: the reference engine traces only with bvh2 or none (it is the 4-wide BVH's arbiter)";
  if (!o.checkpoint_file.empty() && o.engine == Engine::kReference)
    return "--checkpoint needs a pass-based engine (--engine wavefront or megakernel)";
  if (!o.dump_queues.empty() && o.engine != Engine::kWavefront)
    return "--dump-queues needs the wavefront engine (the only one with queues)";
  if (o.queue_order_shading && o.engine != Engine::kWavefront)
    return "--shade-in-queue-order needs the wavefront engine (the only one with queues)";
  if (!o.merge.empty() && !o.scene_path.empty())
    return "--merge assembles parts made by --shard and takes no scene (got " + o.scene_path + ")";
  if (o.shard_count > 0 && !o.convergence_csv.empty()) return "--shard and --convergence-csv do not go together";
  if (o.shard_count > 0 && !o.checkpoint_file.empty())
    return "--shard renders its share in one go; rerun a shard that failed instead of --checkpoint";
  if (o.serve_port >= 0) return validate_live(o);
  const char* estimate_flag = o.target_error > 0.0     ? "--target-error"
                              : o.time_limit > 0.0     ? "--time"
                              : !o.error_image.empty() ? "--error-image"
                                                       : nullptr;
  if (estimate_flag && o.engine == Engine::kReference)
    return std::string(estimate_flag) + " needs a pass-based engine (--engine wavefront or megakernel)";
  if (estimate_flag && o.shard_count > 0)
    return std::string(estimate_flag) + " needs the whole image in one process; not with --shard";
  if (o.stops_early() && !o.convergence_csv.empty())
    return std::string(estimate_flag) + " and --convergence-csv do not go together (it renders every power of two)";
  return {};
}

/// Whether `token` is one of this program's flags ("-q", "--output", "--rr=0.5").
bool is_flag(const CLI::App& app, std::string_view token) {
  if (token.size() < 2 || token[0] != '-') return false;
  return app.get_option_no_throw(std::string(token.substr(0, token.find('=')))) != nullptr;
}

/// What the values of a multi-valued flag are, for messages.
std::string value_names(const CLI::Option& opt) {
  if (opt.check_sname("r")) return "W H";
  if (opt.check_sname("a")) return "BATCH TOL";
  if (opt.check_sname("p")) return "X Y DX DY";
  if (opt.check_lname("merge")) return "OUT PART...";
  return "values";
}

/// CLI11 takes the token after a valued flag as its value even when that
/// token is another flag ("-f -q" would write a file named "-q"): report such
/// a missing value, and too few values for -r, -a and -p, before CLI11 parses.
std::string check_value_counts(const CLI::App& app, int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    std::string_view arg = argv[i];
    if (!is_flag(app, arg) || arg.find('=') != std::string_view::npos) continue;
    const CLI::Option* opt = app.get_option_no_throw(std::string(arg));
    if (opt->get_items_expected_max() == 0) continue;  // a flag without values
    int need = opt->get_items_expected_min();
    for (int k = 1; k <= need; ++k) {
      if (i + k < argc && !is_flag(app, argv[i + k])) continue;
      std::string next = i + k < argc ? std::string(" before ") + argv[i + k] : "";
      if (need == 1) return std::string(arg) + ": missing value" + next;
      return std::string(arg) + ": needs " + std::to_string(need) + " values (" + value_names(*opt) + "), got " +
             std::to_string(k - 1) + next;
    }
    i += need;
  }
  return {};
}

/// CLI11's message on one line.
std::string parse_error_line(const CLI::ParseError& e) {
  std::string msg = e.what();
  for (char& c : msg)
    if (c == '\n' || c == '\r') c = ' ';
  return msg + " (see --help)";
}

}  // namespace

const char* engine_name(Engine e) { return kEngines[static_cast<size_t>(e)]; }

const char* accel_name(AccelChoice a) { return kAccels[static_cast<size_t>(a)]; }

namespace {

/// Declares every flag; values land in `raw` as text, paths and switches in `o`.
void add_options(CLI::App& app, Options& o, RawValues& raw) {
  app.get_formatter()->column_width(34);
  auto valued = [&](const char* names, std::string& text, const char* help, const char* type) {
    app.add_option(names, text, help)->type_name(type);
  };
  auto integer = [&](const char* names, std::string& text, const char* help) { valued(names, text, help, "INT"); };
  auto path = [&](const char* names, std::string& text, const char* help) { valued(names, text, help, "FILE"); };
  path("scene", o.scene_path, "COLLADA scene file (.dae)");
  integer("-s,--samples", raw.samples, "Camera rays per pixel (maximum, with adaptive sampling); 1");
  integer("-l,--light-samples", raw.light_samples, "Samples per area light (and sky) per shading point; 1");
  integer("-t,--threads", raw.threads, "Worker threads; 1");
  integer("-m,--max-depth", raw.max_depth, "Maximum ray depth (bounces); 1");
  // allow_extra_args(false): a multi-valued flag takes exactly its values, so
  // "-r 480 360 scene.dae" leaves the scene to the positional argument.
  app.add_option("-r,--resolution", raw.resolution, "Output size W H; 800 600")
      ->expected(2)
      ->allow_extra_args(false)
      ->type_name("INT");
  path("-f,--output", o.output_path, "Output image (.png, or .pfm for linear float)");
  app.add_option("-a,--adaptive", raw.adaptive,
                 "Adaptive sampling BATCH TOL (TOL 0 turns it off); 32 0, off (--cs184-compat: 32 0.05)")
      ->expected(2)
      ->allow_extra_args(false)
      ->type_name("NUMBER");
  app.add_flag("-H,--hemisphere", raw.hemisphere, "Uniform hemisphere sampling for direct light");
  path("-c,--camera", o.camera_file, "Camera settings file");
  valued("-b,--lens-radius", raw.lens_radius, "Thin lens: aperture radius in scene units (0: pinhole); 0", "NUMBER");
  valued("-d,--focal-distance", raw.focal_distance, "Thin lens: distance to the plane in focus; the scene's centre",
         "NUMBER");
  path("-e,--envmap", o.environment_map, "Environment light: a lat-long OpenEXR map replacing the sky");
  app.add_option("-p,--region", raw.region, "Render only the region X Y DX DY (top-left origin)")
      ->expected(4)
      ->allow_extra_args(false)
      ->type_name("INT");
  valued("--engine", raw.engine, "Render engine: reference, wavefront or megakernel; wavefront", "NAME");
  valued("--bvh", raw.bvh,
         "Acceleration structure: bvh4, bvh2 (midpoint split) or none (brute force); bvh4 (bvh2 for the "
         "reference engine)",
         "NAME");
  integer("--leaf-size", raw.leaf_size, "Maximum primitives per leaf of the bvh2 build; 4");
  valued("--presplit", raw.presplit,
         "BVH4: pre-split long diagonal triangles before the build, up to B extra references per "
         "triangle (0 to 16); 0",
         "B");
  integer("--seed", raw.seed, "Random seed; 0");
  valued("--rr", raw.rr, "Russian roulette continuation probability (--rr-mode fixed); 0.8 (--cs184-compat: 0.65)",
         "NUMBER");
  valued("--rr-mode", raw.rr_mode, "Russian roulette: fixed (--rr) or throughput (continue with max(beta))", "NAME");
  valued("--direct", raw.direct,
         "Direct light: mis (light samples + BSDF, power heuristic), light (importance sampling only), "
         "hemisphere (= -H) or cosine; mis (--cs184-compat: light)",
         "NAME");
  valued("--sampler", raw.sampler,
         "Sample source: sobol (Owen-scrambled, stratified) or independent; sobol (--cs184-compat: independent)",
         "NAME");
  valued("--bounces", raw.bounces, "accumulate, only-m (only the m-th bounce), direct or indirect", "NAME");
  app.add_flag("--normals", raw.normals, "Normal shading instead of path tracing");
  app.add_flag("--cs184-compat", raw.cs184,
               "Reproduce the course renderer: its area-light glow and pdf, invisible sky, 800x600 framing, "
               "truncated PNG values, and its defaults (independent numbers, light sampling, -a 32 0.05, --rr 0.65)");
  app.add_flag("--cs184-framing", o.cs184_framing, "Crop of the 800x600 view, as the course renderer frames -r");
  path("--write-camera", o.write_camera_file, "Also write the render's camera settings file");
  path("--export-scene", o.export_scene,
       "Write the scene as this renderer reads it (JSON: geometry, materials, lights, the camera at -r) and exit");
  valued("--exr-pixel", raw.exr_pixel,
         "Pixel type of an OpenEXR output (-f out.exr): float (32-bit) or half (16-bit); float", "TYPE");
  app.add_flag("--scene-info", o.scene_info,
               "Print what the scene file holds as loaded (nodes, meshes, materials, lights, camera) and what the "
               "loader ignored or changed, then exit");
  path("--checkpoint", o.checkpoint_file,
       "Save the accumulated state to FILE periodically and on Ctrl-C; resume from it if it exists");
  valued("--checkpoint-every", raw.checkpoint_every, "Seconds between checkpoint saves; 60", "NUMBER");
  path("--variance", o.variance_file, "Also write each pixel's variance of its mean (grey PFM)");
  path("--error-image", o.error_image,
       "Also write each pixel's estimated RMSE against the converged image (grey PFM; pass-based engines, "
       "4 samples per pixel or more)");
  valued("--target-error", raw.target_error,
         "Render until the estimated relative RMSE is at most E, stopping only at power-of-two sample counts "
         "(-s, 65536 unless given, is the most it takes)",
         "E");
  valued("--time", raw.time_limit,
         "Render for at most about T seconds, stopping at the last power-of-two sample count that fits "
         "(-s, 65536 unless given, is the most it takes)",
         "T");
  path("--reference", o.reference_image, "Converged reference image (PFM) for --convergence-csv");
  path("--convergence-csv", o.convergence_csv,
       "Render 1, 2, 4, ... spp up to -s and log time, rays and error against --reference as CSV");
  app.add_option("--label", o.label, "Method name written in the convergence CSV")->type_name("TEXT");
  app.add_flag("--convergence-restart", o.convergence_restart,
               "Render each sample count of --convergence-csv from the start, as one render of that many samples "
               "(its time: the BVH build and that render), instead of continuing from the previous count");
  integer("--tile", raw.tile, "Tile edge in pixels of the work mpirun ranks and --shard jobs share; 64");
  app.add_option("--shard", raw.shard,
                 "Render share I of N (I/N, I from 0) of the tiles into the tile set -f names, for --merge")
      ->type_name("I/N");
  app.add_option("--merge", o.merge, "Assemble the image OUT from the tile sets PART... of every --shard")
      ->expected(2, 1 << 20)
      ->type_name("OUT PART");
  app.add_flag("--stats", o.stats, "Print per-stage statistics");
  app.add_flag("--memory", o.memory, "Print the bytes of every structure the render allocates and the peak RSS");
  valued("--trace", raw.trace,
         "Wavefront: queue (every queue whole through the queue tracer, which picks each queue's method) "
         "or single (every ray on its own, for comparison); queue",
         "NAME");
  app.add_flag(
      "--shade-in-queue-order", o.queue_order_shading,
      "Wavefront: shade bounce hits in the order their rays were queued, not sorted by the cell of their "
      "hit points (the same image but for which of two triangles at exactly the same t is reported; for timing "
      "what the sort buys)");
  path("--dump-queues", o.dump_queues,
       "Wavefront: write every queue the render traces into DIR as ray files (<kind>_d<depth>.rays) with the "
       "scene's triangles (scene.tris), for trace_rays and bench_trace");
  app.add_flag("--count-tests", o.count_tests,
               "Count primitive intersection tests per ray for the report (BVH4 engines run slower)");
  valued("--isa", raw.isa,
         "SIMD instruction set of the engines: auto (the widest this CPU runs), sse4.2, avx2, avx512 or neon; "
         "also PT_ISA in the environment; auto",
         "NAME");
  app.add_flag("--list-isa", raw.list_isa,
               "List the instruction sets compiled in, whether this CPU runs them, and exit");
  app.add_flag("-q,--quiet", o.quiet, "No progress bar or summary");
  app.add_flag("--serve", raw.serve,
               "--serve [PORT]: serve the live view of the scene at http://127.0.0.1:PORT/ until Ctrl-C (PORT 8184; 0 "
               "picks a free one); -s defaults to 1024 and -t to every core");
  app.add_option("--bind", o.bind_address, "Address the live view listens on; 127.0.0.1")->type_name("ADDR");
}

/// Takes the optional PORT of --serve (and --serve=PORT) out of the command
/// line, which CLI11 then parses with --serve as a plain flag.
std::vector<std::string> take_serve_port(int argc, char** argv, RawValues& raw) {
  std::vector<std::string> args(argv, argv + argc);
  for (size_t i = 1; i < args.size(); ++i) {
    if (args[i].rfind("--serve=", 0) == 0) {
      raw.serve_port = args[i].substr(8);
      args[i] = "--serve";
    } else if (args[i] == "--serve" && i + 1 < args.size() && !args[i + 1].empty() &&
               args[i + 1].find_first_not_of("0123456789") == std::string::npos) {
      raw.serve_port = args[i + 1];
      args.erase(args.begin() + long(i) + 1);
    }
  }
  return args;
}

/// --list-isa: one line per compiled level.
void print_isa_list() {
  Isa best = best_isa();
  for (Isa isa : compiled_isas())
    std::cout << isa_name(isa) << " " << isa_lanes(isa) << " lanes "
              << (cpu_supports(isa) ? "supported" : "unsupported") << (isa == best ? " auto" : "") << "\n";
}

}  // namespace

ParseResult parse_command_line(int argc, char** argv) {
  Options o;
  RenderSettings& s = o.settings;
  RawValues raw;
  CLI::App app{"Path tracer for CS184 COLLADA scenes. Renders SCENE (default: the built-in Cornell box)."};
  add_options(app, o, raw);
  std::vector<std::string> args = take_serve_port(argc, argv, raw);
  std::vector<char*> arg_ptrs;
  for (std::string& a : args) arg_ptrs.push_back(a.data());
  argc = int(arg_ptrs.size());
  argv = arg_ptrs.data();

  if (std::string err = check_value_counts(app, argc, argv); !err.empty()) {
    std::cerr << "error: " << err << "\n";
    return {std::nullopt, 2};
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    std::cout << app.help();
    return {std::nullopt, 0};
  } catch (const CLI::ParseError& e) {
    std::cerr << "error: " << parse_error_line(e) << "\n";
    return {std::nullopt, 2};
  }

  if (raw.list_isa) {
    print_isa_list();
    return {std::nullopt, 0};
  }
  Converter converter(app, o);
  converter.convert(raw);
  std::string err = converter.error.empty() ? validate(o) : converter.error;
  if (!err.empty()) {
    std::cerr << "error: " << err << "\n";
    return {std::nullopt, 2};
  }
  s.shading = raw.normals ? ShadingMode::kNormals : ShadingMode::kPathTrace;
  if (raw.cs184) {
    s.cs184_light_quirk = true;
    s.cs184_invisible_sky = true;
    s.cs184_light_pdf = true;
    s.cs184_materials = true;
    // The course renderer's defaults where a flag does not say otherwise.
    if (app.count("--sampler") == 0) s.sampler = PixelSampler::kIndependent;
    if (app.count("--direct") == 0 && !raw.hemisphere) s.direct = DirectLighting::kLightSampling;
    if (app.count("-a") == 0) s.adaptive_tolerance = 0.05f;
    if (app.count("--rr") == 0) s.rr_continue = 0.65f;
    o.cs184_framing = true;
    o.cs184_png = true;
  }
  return {o, 0};
}

}  // namespace pt::cli
