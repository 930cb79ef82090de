// Checkpoint format: "PTCHECK2", fingerprint length + text, samples_done,
// pixel count, the PixelAccumulator array, and an FNV-1a checksum of all of it.
#include "checkpoint.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>

#include "atomic_file.h"
#include "binary_io.h"
#include "read_file.h"
#include "scene_error.h"

namespace pt {
namespace {

// 2: PixelAccumulator keeps its means at powers of two (88 bytes, 48 in version 1).
constexpr char kMagic[8] = {'P', 'T', 'C', 'H', 'E', 'C', 'K', '2'};

}  // namespace

/// FNV-1a of the map's texels, read back through its lookup at texel centres.
uint64_t environment_hash(const EnvironmentMap& env) {
  std::vector<float3> texels;
  texels.reserve(size_t(env.width()) * env.height());
  for (int j = 0; j < env.height(); ++j)
    for (int i = 0; i < env.width(); ++i) texels.push_back(env.lookup(i + 0.5f, j + 0.5f));
  return fnv1a(texels.data(), texels.size() * sizeof(float3));
}

std::string render_fingerprint(const std::string& engine, const Scene& scene, const Camera& c,
                               const RenderSettings& rs) {
  std::ostringstream o;
  o.precision(9);
  o << "engine=" << engine << " scene=" << scene.name << " tris=" << scene.triangles.size()
    << " spheres=" << scene.spheres.size()
    << " geometry=" << fnv1a(scene.positions.data(), scene.positions.size() * sizeof(float3))
    << " materials=" << fnv1a(scene.materials.data(), scene.materials.size() * sizeof(Material))
    << " camera=" << fnv1a(&c, sizeof c) << " size=" << rs.width << "x" << rs.height << " s=" << rs.samples_per_pixel
    << " l=" << rs.light_samples << " m=" << rs.max_depth << " a=" << rs.adaptive_batch << "," << rs.adaptive_tolerance
    << " rr=" << rs.rr_continue << " rr_mode=" << int(rs.roulette) << " sampler=" << int(rs.sampler)
    << " direct=" << int(rs.direct) << " bounces=" << int(rs.bounces) << " shading=" << int(rs.shading)
    << " seed=" << rs.seed << " quirks=" << rs.cs184_light_quirk << rs.cs184_invisible_sky << rs.cs184_light_pdf
    << rs.cs184_materials;
  if (scene.environment)
    o << " environment=" << scene.environment->width() << "x" << scene.environment->height() << ","
      << environment_hash(*scene.environment);
  if (rs.region)
    o << " region=" << rs.region->x << "," << rs.region->y << "," << rs.region->width << "," << rs.region->height;
  return o.str();
}

void save_checkpoint(const std::filesystem::path& path, const std::string& fingerprint, const Accumulation& acc) {
  std::string out(kMagic, sizeof kMagic);
  put(out, static_cast<uint32_t>(fingerprint.size()));
  out += fingerprint;
  put(out, acc.samples_done);
  put(out, static_cast<uint64_t>(acc.pixels.size()));
  out.append(reinterpret_cast<const char*>(acc.pixels.data()), acc.pixels.size() * sizeof(PixelAccumulator));
  close_frame(out);
  write_file_atomically(path, out);
}

std::optional<Accumulation> load_checkpoint(const std::filesystem::path& path, const std::string& fingerprint,
                                            size_t pixel_count, uint32_t max_samples) {
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) return std::nullopt;
  // Header, fingerprint and checksum take far less than the slack allowed here.
  const uint64_t max_bytes = (uint64_t(1) << 20) + uint64_t(pixel_count) * sizeof(PixelAccumulator);
  std::string data = read_regular_file(path, "checkpoint", max_bytes);
  auto corrupt = [&](const std::string& what) {
    return InputError(path.string() + ": not a usable checkpoint: " + what);
  };
  std::string_view rest = frame_body(data, kMagic, corrupt);
  uint32_t fp_len = 0;
  if (!take(rest, fp_len) || rest.size() < fp_len) throw corrupt("truncated");
  if (rest.substr(0, fp_len) != fingerprint)
    throw InputError(path.string() + ": checkpoint was written for a different render (" +
                     std::string(rest.substr(0, std::min<size_t>(fp_len, 120))) + "...)");
  rest.remove_prefix(fp_len);
  Accumulation acc;
  uint64_t n = 0;
  if (!take(rest, acc.samples_done) || !take(rest, n) || n != pixel_count ||
      rest.size() != n * sizeof(PixelAccumulator))
    throw corrupt("pixel data does not match the image size");
  acc.pixels.resize(n);
  std::memcpy(acc.pixels.data(), rest.data(), rest.size());
  if (acc.samples_done > max_samples) throw corrupt("more samples done than the render takes");
  for (const PixelAccumulator& p : acc.pixels) {
    bool finite = std::isfinite(p.sum_r) && std::isfinite(p.sum_g) && std::isfinite(p.sum_b) &&
                  std::isfinite(p.moments.s1) && std::isfinite(p.moments.s2);
    for (const auto& rgb : p.at_powers)
      for (float v : rgb) finite = finite && std::isfinite(v);
    if (!finite || p.samples > max_samples || p.converged > 1 || p.moments.s2 < 0.0)
      throw corrupt("pixel values that no render of these settings produces");
  }
  return acc;
}

}  // namespace pt
