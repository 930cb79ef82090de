// The pathtracer command line: the CS184 flags (-s -l -t -m -r -f -a -H -c -p),
// their long forms, and this renderer's additions. Parsing validates every
// value and reports the first bad one in a single line.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "io/image_output.h"
#include "kernels/simd/isa.h"
#include "kernels/render/render_settings.h"
#include "wavefront/trace_mode.h"

namespace pt::cli {

enum class Engine { kReference, kWavefront, kMegakernel };
enum class AccelChoice { kBvh4, kBvh2, kNone };

struct Options {
  std::string scene_path;                 ///< empty: the built-in default scene
  std::string output_path;                ///< -f; empty: <scene name>.png
  std::string camera_file;                ///< -c
  std::string environment_map;            ///< -e: lat-long EXR replacing the sky
  std::optional<float> lens_radius;       ///< -b: thin-lens aperture radius
  std::optional<float> focal_distance;    ///< -d: thin-lens focal distance
  std::string write_camera_file;          ///< --write-camera
  std::string export_scene;               ///< --export-scene: write the scene as JSON and exit
  ExrPixel exr_pixel = ExrPixel::kFloat;  ///< --exr-pixel: the pixel type of an .exr output
  bool scene_info = false;                ///< --scene-info: print what the scene holds and what was ignored; exit
  std::string checkpoint_file;            ///< --checkpoint: save / resume accumulated state
  double checkpoint_every = 60.0;         ///< seconds between checkpoint saves
  std::string variance_file;              ///< --variance: per-pixel variance PFM
  std::string error_image;                ///< --error-image: per-pixel estimated RMSE PFM
  double target_error = 0.0;              ///< --target-error: stop at this estimated relative RMSE (0: no target)
  double time_limit = 0.0;                ///< --time: stop within this many seconds (0: no limit)
  std::string reference_image;            ///< --reference: converged image for --convergence-csv
  std::string convergence_csv;            ///< --convergence-csv: error vs time log
  std::string label = "render";           ///< --label: method name in the CSV
  bool convergence_restart = false;       ///< --convergence-restart: each sample count rendered from the start
  int tile_size = 64;                     ///< --tile: tile edge for mpirun and --shard
  int shard_index = 0, shard_count = 0;   ///< --shard I/N (count 0: not a shard)
  /// --target-error or --time: the render stops at a power-of-two sample count.
  bool stops_early() const { return target_error > 0.0 || time_limit > 0.0; }
  std::vector<std::string> merge;          ///< --merge OUT PART...: the output, then the parts
  int serve_port = -1;                     ///< --serve [PORT]: the live view's port (0: any free one); -1: no live view
  std::string bind_address = "127.0.0.1";  ///< --bind: the live view's address
  RenderSettings settings;
  Engine engine = Engine::kWavefront;
  AccelChoice accel = AccelChoice::kBvh4;
  uint32_t max_leaf_size = 4;
  float presplit_budget = 0.0f;  ///< --presplit: BVH4 pre-splitting budget (Bvh4Options)
  bool cs184_framing = false;
  bool cs184_png = false;  ///< --cs184-compat: PNG values truncated as the course renderer does
  bool quiet = false;
  bool stats = false;
  bool memory = false;                          ///< --memory: print bytes per structure and peak RSS
  wf::TraceMode trace = wf::TraceMode::kQueue;  ///< --trace
  std::string dump_queues;                      ///< --dump-queues DIR: write every queue traced as ray files
  bool queue_order_shading = false;             ///< --shade-in-queue-order: bounce hits not sorted by hit point
  bool count_tests = false;                     ///< --count-tests: count primitive tests (slower)
  Isa isa = Isa::kSse42;                        ///< --isa, else PT_ISA, else the widest level the CPU runs
};

/// Outcome of parsing: options to run with, or an exit code (0 after --help
/// and --list-isa).
struct ParseResult {
  std::optional<Options> options;
  int exit_code = 0;
};

ParseResult parse_command_line(int argc, char** argv);

const char* engine_name(Engine e);
const char* accel_name(AccelChoice a);

}  // namespace pt::cli
