// Triangle, ray and hit files.
#include "ray_files.h"

#include <cstring>

#include "atomic_file.h"
#include "read_file.h"
#include "scene_error.h"

namespace pt {
namespace {

/// The file's bytes, a whole number of `record`-byte records.
std::string read_all(const std::filesystem::path& path, const char* what, size_t record) {
  std::string bytes = read_regular_file(path, what, uint64_t(1) << 36);
  if (bytes.size() % record != 0)
    throw InputError(path.string() + ": size " + std::to_string(bytes.size()) + " is not a multiple of " +
                     std::to_string(record) + " bytes");
  return bytes;
}

void write_all(const std::filesystem::path& path, const void* data, size_t bytes) {
  write_file_atomically(path, std::string_view(static_cast<const char*>(data), bytes));
}

}  // namespace

Scene read_triangle_file(const std::filesystem::path& path) {
  std::string bytes = read_all(path, "triangle file", 9 * sizeof(float));
  Scene s;
  s.name = path.filename().string();
  s.positions.resize(bytes.size() / sizeof(float3));
  std::memcpy(s.positions.data(), bytes.data(), bytes.size());
  for (uint32_t i = 0; i < s.positions.size(); i += 3) s.triangles.push_back({i, i + 1, i + 2});
  s.mesh_triangle_count = static_cast<uint32_t>(s.triangles.size());
  s.bounds = compute_scene_bounds(s);
  return s;
}

void write_triangle_file(const std::filesystem::path& path, const Scene& scene) {
  std::vector<float3> soup;
  soup.reserve(scene.triangles.size() * 3);
  for (const TriangleIndices& t : scene.triangles)
    soup.insert(soup.end(), {scene.positions[t.v0], scene.positions[t.v1], scene.positions[t.v2]});
  write_all(path, soup.data(), soup.size() * sizeof(float3));
}

std::vector<Ray> read_ray_file(const std::filesystem::path& path) {
  std::string bytes = read_all(path, "ray file", sizeof(Ray));
  std::vector<Ray> rays(bytes.size() / sizeof(Ray));
  std::memcpy(rays.data(), bytes.data(), bytes.size());
  return rays;
}

void write_ray_file(const std::filesystem::path& path, std::span<const Ray> rays) {
  write_all(path, rays.data(), rays.size() * sizeof(Ray));
}

void write_hit_file(const std::filesystem::path& path, const std::vector<Hit>& hits) {
  std::vector<uint32_t> out;
  out.reserve(hits.size() * 2);
  for (const Hit& h : hits) {
    uint32_t t;
    std::memcpy(&t, &h.t, sizeof t);
    out.insert(out.end(), {t, h.valid() ? h.prim : kInvalidId});
  }
  write_all(path, out.data(), out.size() * sizeof(uint32_t));
}

}  // namespace pt
