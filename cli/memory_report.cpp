// The --memory report: sizes read from the structures, and the formatting.
#include "memory_report.h"

#include <sys/resource.h>

#include <cstdio>

#include "io/image_output.h"
#include "kernels/render/pixel_accumulator.h"
#include "wavefront/wave_context.h"

namespace pt::cli {
namespace {

template <class V>
Footprint bytes_of(const V& v) {
  return {v.capacity() * sizeof(typename V::value_type), v.size() * sizeof(typename V::value_type)};
}
Footprint operator+(Footprint a, Footprint b) { return {a.allocated + b.allocated, a.used + b.used}; }
Footprint exactly(size_t bytes) { return {bytes, bytes}; }

const char* unit_name(MemoryScale s) {
  switch (s) {
    case MemoryScale::kTriangle: return "triangle";
    case MemoryScale::kPixel: return "pixel";
    case MemoryScale::kThread: return "thread";
    case MemoryScale::kFixed: return "";
  }
  return "";
}

size_t unit_count(const MemoryReport& r, MemoryScale s) {
  switch (s) {
    case MemoryScale::kTriangle: return r.triangles;
    case MemoryScale::kPixel: return r.pixels;
    case MemoryScale::kThread: return static_cast<size_t>(r.threads);
    case MemoryScale::kFixed: return 0;
  }
  return 0;
}

void add(MemoryReport& r, std::string name, Footprint f, MemoryScale scale, bool transient = false) {
  r.lines.push_back({std::move(name), f.allocated, f.used, scale, transient});
}

}  // namespace

size_t MemoryReport::total() const {
  size_t sum = 0;
  for (const MemoryLine& l : lines)
    if (!l.transient) sum += l.bytes;
  return sum;
}

void add_scene_memory(MemoryReport& r, const Scene& s) {
  r.triangles = s.triangles.size();
  add(r, "scene: vertex positions", bytes_of(s.positions), MemoryScale::kTriangle);
  add(r, "scene: vertex normals", bytes_of(s.normals), MemoryScale::kTriangle);
  add(r, "scene: triangle indices", bytes_of(s.triangles), MemoryScale::kTriangle);
  add(r, "scene: triangle materials", bytes_of(s.triangle_material), MemoryScale::kTriangle);
  add(r, "scene: spheres", bytes_of(s.spheres), MemoryScale::kFixed);
  add(r, "scene: materials", bytes_of(s.materials), MemoryScale::kFixed);
  add(r, "scene: lights", bytes_of(s.area_lights) + bytes_of(s.point_lights) + bytes_of(s.directional_lights),
      MemoryScale::kFixed);
  if (s.environment)
    add(r, "scene: environment map (texels, CDFs)", exactly(s.environment->bytes()), MemoryScale::kFixed);
}

void add_render_memory(MemoryReport& r, const RenderSettings& rs, const Scene& scene, const RenderOutput& out,
                       const EngineFootprint& e, const std::filesystem::path& output) {
  const size_t pixels = size_t(rs.width) * rs.height;
  const size_t prims = scene.primitive_count();
  r.pixels = pixels;
  r.threads = rs.threads;
  add(r, e.accel_name + ": nodes and leaves", e.accel, MemoryScale::kTriangle);
  if (e.accel_name != "none")
    add(r, "bvh build inputs (boxes, centres)", exactly(prims * (sizeof(BBox) + sizeof(float3))),
        MemoryScale::kTriangle, true);
  if (e.engine == Engine::kWavefront) {
    wf::MaterialArrays mats(scene);
    add(r, "wavefront: material arrays", exactly(mats.bytes()), MemoryScale::kFixed);
    add(r, "wavefront: wave queues", exactly(e.queue_bytes), MemoryScale::kThread);
    add(r, "wavefront: queue tracer lists", exactly(e.tracer_bytes), MemoryScale::kThread);
  }
  if (e.engine != Engine::kReference) {
    const size_t rendered = size_t(rs.area().width) * rs.area().height;  // the accumulators cover the region
    add(r, "pass driver: pixel accumulators", exactly(rendered * sizeof(PixelAccumulator)), MemoryScale::kPixel);
    add(r, "pass driver: pixel lists (order, active, todo)", exactly(3 * rendered * sizeof(uint32_t)),
        MemoryScale::kPixel);
  }
  add(r, "film: radiance", bytes_of(out.film.radiance), MemoryScale::kPixel);
  add(r, "film: samples", bytes_of(out.film.samples), MemoryScale::kPixel);
  add(r, "film: variance", bytes_of(out.film.variance), MemoryScale::kPixel);
  bool pfm = image_format_for(output) == ImageFormat::kPfm;
  add(r, pfm ? "output: PFM encoding" : "output: PNG pixels before compression", exactly(pixels * (pfm ? 12 : 3)),
      MemoryScale::kPixel, true);
}

size_t peak_resident_bytes() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<size_t>(ru.ru_maxrss) * 1024;  // Linux reports kilobytes
}

std::string format_memory_report(const MemoryReport& r) {
  std::string text;
  char line[200];
  std::snprintf(line, sizeof line, "%-48s %12s %12s  %s\n", "structure", "allocated", "in use", "allocated per unit");
  text += line;
  for (const MemoryLine& l : r.lines) {
    size_t n = unit_count(r, l.scale);
    char per[48] = "";
    double each = n > 0 ? double(l.bytes) / double(n) : 0.0;
    if (each >= 10240) std::snprintf(per, sizeof per, "%.1f KiB/%s", each / 1024, unit_name(l.scale));
    else if (n > 0) std::snprintf(per, sizeof per, "%.2f B/%s", each, unit_name(l.scale));
    std::string name = l.structure + (l.transient ? " [transient]" : "");
    std::snprintf(line, sizeof line, "%-48s %12zu %12zu  %s\n", name.c_str(), l.bytes, l.used, per);
    text += line;
  }
  std::snprintf(line, sizeof line, "%-48s %12zu %12s  (%.2f MiB; %zu triangles, %zu pixels, %d threads)\n",
                "total held (without transient lines)", r.total(), "", r.total() / 1048576.0, r.triangles, r.pixels,
                r.threads);
  text += line;
  if (r.peak_rss_bytes) {
    std::snprintf(line, sizeof line, "%-48s %12zu %12s  (%.2f MiB, getrusage)\n", "peak resident set size",
                  r.peak_rss_bytes, "", r.peak_rss_bytes / 1048576.0);
    text += line;
  }
  return text;
}

}  // namespace pt::cli
