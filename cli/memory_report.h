// --memory: what a render allocates, structure by structure (scene arrays, the
// acceleration structure, the engine's per-thread queues, the per-pixel
// buffers and the output encoding), in bytes and per triangle / per pixel /
// per thread, plus the process's peak resident set size. Array sizes are read
// from the structures themselves (vector capacities: what is allocated, not
// what is used); per-pixel state inside an engine is sized from its types.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_options.h"
#include "kernels/render/render_job.h"

namespace pt::cli {

/// What a line's bytes scale with.
enum class MemoryScale { kTriangle, kPixel, kThread, kFixed };

struct MemoryLine {
  std::string structure;
  size_t bytes = 0;  ///< allocated
  size_t used = 0;   ///< of which in use (vector sizes rather than capacities)
  MemoryScale scale = MemoryScale::kFixed;
  bool transient = false;  ///< freed before the render ends (not held with the rest)
};

struct MemoryReport {
  std::vector<MemoryLine> lines;
  size_t triangles = 0, pixels = 0;
  int threads = 1;
  size_t peak_rss_bytes = 0;  ///< 0 when not measured

  /// Sum of the allocated bytes of the lines that are held (not transient).
  size_t total() const;
};

/// Adds one line per array of the scene (positions, normals, triangles,
/// per-triangle materials, spheres, materials, lights) and sets `triangles`.
void add_scene_memory(MemoryReport& report, const Scene& scene);

/// Bytes of one structure: allocated, and of those in use.
struct Footprint {
  size_t allocated = 0, used = 0;
};

/// The engine side of a render: which engine, its accelerator and the
/// bytes of its per-thread queues and of the queue tracer's lists (0 for
/// engines without queues).
struct EngineFootprint {
  Engine engine = Engine::kReference;
  std::string accel_name;  ///< "none" for brute force
  Footprint accel;
  size_t queue_bytes = 0;
  size_t tracer_bytes = 0;
};

/// Adds the engine's lines for a finished render: its accelerator, its
/// queues, its per-pixel state, the film `out` holds and the encoding of
/// `output` (PNG or PFM by extension).
void add_render_memory(MemoryReport& report, const RenderSettings& settings, const Scene& scene,
                       const RenderOutput& out, const EngineFootprint& engine, const std::filesystem::path& output);

/// Peak resident set size of this process so far (getrusage), in bytes.
size_t peak_resident_bytes();

/// The report as an aligned text table, one structure per line.
std::string format_memory_report(const MemoryReport& report);

}  // namespace pt::cli
