// parse_command_line on CLI11, with range checks on every value.
#include "cli_options.h"

#include <cmath>
#include <iostream>
#include <map>

#include <CLI/CLI.hpp>

namespace pt::cli {
namespace {

constexpr int kMaxDimension = 16384;
constexpr int64_t kMaxPixels = int64_t(1) << 27;

/// Returns an error message, or empty if the options are consistent.
std::string validate(const Options& o) {
  const RenderSettings& s = o.settings;
  if (s.samples_per_pixel < 1 || s.samples_per_pixel > (1 << 24)) return "-s: samples per pixel must be 1..16777216";
  if (s.light_samples < 1 || s.light_samples > 4096) return "-l: light samples must be 1..4096";
  if (s.threads < 1 || s.threads > 1024) return "-t: threads must be 1..1024";
  if (s.max_depth < 0 || s.max_depth > 1024) return "-m: maximum depth must be 0..1024";
  if (s.width < 1 || s.height < 1 || s.width > kMaxDimension || s.height > kMaxDimension ||
      int64_t(s.width) * s.height > kMaxPixels)
    return "-r: resolution must be 1..16384 on each side and at most 2^27 pixels";
  if (s.adaptive_batch < 1) return "-a: batch size must be at least 1";
  if (!(s.adaptive_tolerance >= 0.0f) || !std::isfinite(s.adaptive_tolerance))
    return "-a: tolerance must be a finite number >= 0 (0 turns adaptive sampling off)";
  if (!(s.rr_continue > 0.0f && s.rr_continue <= 1.0f)) return "--rr: continuation probability must be in (0, 1]";
  if (s.region) {
    const Region& r = *s.region;
    if (r.width < 1 || r.height < 1 || r.x < 0 || r.y < 0 || int64_t(r.x) + r.width > s.width ||
        int64_t(r.y) + r.height > s.height)
      return "-p: region " + std::to_string(r.x) + " " + std::to_string(r.y) + " " + std::to_string(r.width) + " " +
             std::to_string(r.height) + " is not inside the " + std::to_string(s.width) + "x" +
             std::to_string(s.height) + " image";
  }
  if (o.max_leaf_size < 1 || o.max_leaf_size > 64) return "--leaf-size must be 1..64";
  if (!(o.checkpoint_every > 0.0) || !std::isfinite(o.checkpoint_every))
    return "--checkpoint-every must be a positive number of seconds";
  if (o.reference_image.empty() != o.convergence_csv.empty())
    return "--reference and --convergence-csv go together";
  if (!o.checkpoint_file.empty() && o.engine == Engine::kReference)
    return "--checkpoint needs a pass-based engine (--engine wavefront or megakernel)";
  return {};
}

}  // namespace

const char* engine_name(Engine e) {
  switch (e) {
    case Engine::kReference: return "reference";
    case Engine::kWavefront: return "wavefront";
    case Engine::kMegakernel: return "megakernel";
  }
  return "?";
}

const char* accel_name(AccelChoice a) {
  switch (a) {
    case AccelChoice::kBvh4: return "bvh4";
    case AccelChoice::kBvh2: return "bvh2";
    case AccelChoice::kNone: return "none";
  }
  return "?";
}

ParseResult parse_command_line(int argc, char** argv) {
  Options o;
  RenderSettings& s = o.settings;
  CLI::App app{"Path tracer for CS184 COLLADA scenes. Renders SCENE (default: the built-in Cornell box)."};
  app.get_formatter()->column_width(34);

  std::vector<int> resolution, region;
  std::vector<std::string> adaptive;
  std::string bounce_mode = "accumulate", direct_mode, sampler = "independent", rr_mode = "fixed";
  bool hemisphere = false, normals = false, cs184 = false;

  app.add_option("scene", o.scene_path, "COLLADA scene file (.dae)");
  app.add_option("-s,--samples", s.samples_per_pixel, "Camera rays per pixel (maximum, with adaptive sampling)");
  app.add_option("-l,--light-samples", s.light_samples, "Samples per area light (and sky) per shading point");
  app.add_option("-t,--threads", s.threads, "Worker threads");
  app.add_option("-m,--max-depth", s.max_depth, "Maximum ray depth (bounces)");
  app.add_option("-r,--resolution", resolution, "Output size W H")->expected(2);
  app.add_option("-f,--output", o.output_path, "Output image (.png, or .pfm for linear float)");
  app.add_option("-a,--adaptive", adaptive, "Adaptive sampling BATCH TOL (TOL 0 turns it off)")->expected(2);
  app.add_flag("-H,--hemisphere", hemisphere, "Uniform hemisphere sampling for direct light");
  app.add_option("-c,--camera", o.camera_file, "Camera settings file");
  app.add_option("-p,--region", region, "Render only the region X Y DX DY (top-left origin)")->expected(4);
  app.add_option("--engine", o.engine, "Render engine")
      ->transform(CLI::CheckedTransformer(std::map<std::string, Engine>{{"reference", Engine::kReference},
                                                                        {"wavefront", Engine::kWavefront},
                                                                        {"megakernel", Engine::kMegakernel}}));
  app.add_option("--bvh", o.accel, "Acceleration structure: bvh4, bvh2 (midpoint split) or none (brute force)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, AccelChoice>{
          {"bvh4", AccelChoice::kBvh4}, {"bvh2", AccelChoice::kBvh2}, {"none", AccelChoice::kNone}}));
  app.add_option("--leaf-size", o.max_leaf_size, "Maximum primitives per leaf of the bvh2 build");
  app.add_option("--seed", s.seed, "Random seed");
  app.add_option("--rr", s.rr_continue, "Russian roulette continuation probability (--rr-mode fixed)");
  app.add_option("--rr-mode", rr_mode, "Russian roulette: fixed (--rr) or throughput (continue with max(beta))")
      ->check(CLI::IsMember({"fixed", "throughput"}));
  app.add_option("--direct", direct_mode,
                 "Direct light: light (importance sampling), hemisphere (= -H), cosine, or mis (lights + BSDF)")
      ->check(CLI::IsMember({"light", "hemisphere", "cosine", "mis"}));
  app.add_option("--sampler", sampler, "Sample source: independent or sobol (Owen-scrambled)")
      ->check(CLI::IsMember({"independent", "sobol"}));
  app.add_option("--bounces", bounce_mode, "accumulate, only-m (only the m-th bounce), direct or indirect")
      ->check(CLI::IsMember({"accumulate", "only-m", "direct", "indirect"}));
  app.add_flag("--normals", normals, "Normal shading instead of path tracing");
  app.add_flag("--cs184-compat", cs184,
               "Reproduce the course renderer's quirks: area-light glow, invisible sky, 800x600 framing");
  app.add_flag("--cs184-framing", o.cs184_framing, "Crop of the 800x600 view, as the course renderer frames -r");
  app.add_option("--write-camera", o.write_camera_file, "Also write the render's camera settings file");
  app.add_option("--checkpoint", o.checkpoint_file,
                 "Save the accumulated state to FILE periodically and on Ctrl-C; resume from it if it exists");
  app.add_option("--checkpoint-every", o.checkpoint_every, "Seconds between checkpoint saves");
  app.add_option("--variance", o.variance_file, "Also write each pixel's variance of its mean (grey PFM)");
  app.add_option("--reference", o.reference_image, "Converged reference image (PFM) for --convergence-csv");
  app.add_option("--convergence-csv", o.convergence_csv,
                 "Render 1, 2, 4, ... spp up to -s and log time, rays and error against --reference as CSV");
  app.add_option("--label", o.label, "Method name written in the convergence CSV");
  app.add_flag("--stats", o.stats, "Print per-stage statistics");
  app.add_flag("--memory", o.memory, "Print the bytes of every structure the render allocates and the peak RSS");
  app.add_flag("-q,--quiet", o.quiet, "No progress bar or summary");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    std::cout << app.help();
    return {std::nullopt, 0};
  } catch (const CLI::ParseError& e) {
    std::cerr << "error: " << e.what() << " (see --help)\n";
    return {std::nullopt, 2};
  }

  if (!resolution.empty()) { s.width = resolution[0]; s.height = resolution[1]; }
  if (!region.empty()) s.region = Region{region[0], region[1], region[2], region[3]};
  if (!adaptive.empty()) {
    try {
      size_t used_batch = 0, used_tol = 0;
      s.adaptive_batch = std::stoi(adaptive[0], &used_batch);
      s.adaptive_tolerance = std::stof(adaptive[1], &used_tol);
      if (used_batch != adaptive[0].size() || used_tol != adaptive[1].size()) throw std::invalid_argument("");
    } catch (const std::exception&) {
      std::cerr << "error: -a: expected an integer BATCH and a number TOL, got \"" << adaptive[0] << " " << adaptive[1]
                << "\"\n";
      return {std::nullopt, 2};
    }
  }
  if (hemisphere && !direct_mode.empty() && direct_mode != "hemisphere") {
    std::cerr << "error: -H and --direct " << direct_mode << " contradict each other\n";
    return {std::nullopt, 2};
  }
  s.direct = hemisphere || direct_mode == "hemisphere" ? DirectLighting::kHemisphere
             : direct_mode == "cosine"                 ? DirectLighting::kCosine
             : direct_mode == "mis"                    ? DirectLighting::kMis
                                                       : DirectLighting::kLightSampling;
  s.sampler = sampler == "sobol" ? PixelSampler::kSobol : PixelSampler::kIndependent;
  s.roulette = rr_mode == "throughput" ? RouletteMode::kThroughput : RouletteMode::kFixed;
  s.shading = normals ? ShadingMode::kNormals : ShadingMode::kPathTrace;
  s.bounces = bounce_mode == "only-m"   ? BounceMode::kOnlyBounceM
              : bounce_mode == "direct" ? BounceMode::kDirectOnly
              : bounce_mode == "indirect" ? BounceMode::kIndirectOnly
                                          : BounceMode::kAccumulate;
  if (cs184) {
    s.cs184_light_quirk = true;
    s.cs184_invisible_sky = true;
    o.cs184_framing = true;
  }
  if (std::string err = validate(o); !err.empty()) {
    std::cerr << "error: " << err << "\n";
    return {std::nullopt, 2};
  }
  return {o, 0};
}

}  // namespace pt::cli
