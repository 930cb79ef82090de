// Scene loading and midpoint subdivision for the benchmark.
#include "bench_scenes.h"

#include <filesystem>
#include <unordered_map>

#include "io/collada_loader.h"

namespace pt::bench {

std::string shared_scene_dir() { return PT_SHARED_SCENES; }

std::optional<Scene> load_triangle_scene(const std::string& file) {
  std::filesystem::path path = std::filesystem::path(shared_scene_dir()) / file;
  if (!std::filesystem::exists(path)) return std::nullopt;
  Scene s = load_collada_file(path).scene;
  s.spheres.clear();
  s.bounds = compute_scene_bounds(s);
  return s;
}

Scene subdivide_scene(const Scene& in, int levels) {
  Scene s = in;
  for (int l = 0; l < levels; ++l) {
    std::unordered_map<uint64_t, uint32_t> midpoint;
    midpoint.reserve(s.triangles.size() * 2);
    auto mid = [&](uint32_t a, uint32_t b) {
      uint64_t key = uint64_t(std::min(a, b)) << 32 | std::max(a, b);
      auto [it, inserted] = midpoint.try_emplace(key, static_cast<uint32_t>(s.positions.size()));
      if (inserted) {
        float3 p = (s.positions[a] + s.positions[b]) * 0.5f;
        s.positions.push_back(p);
      }
      return it->second;
    };
    std::vector<TriangleIndices> tris;
    std::vector<uint32_t> materials;
    tris.reserve(s.triangles.size() * 4);
    materials.reserve(s.triangles.size() * 4);
    for (size_t i = 0; i < s.triangles.size(); ++i) {
      TriangleIndices t = s.triangles[i];
      uint32_t ab = mid(t.v0, t.v1), bc = mid(t.v1, t.v2), ca = mid(t.v2, t.v0);
      tris.insert(tris.end(), {{t.v0, ab, ca}, {ab, t.v1, bc}, {ca, bc, t.v2}, {ab, bc, ca}});
      materials.insert(materials.end(), 4, s.triangle_material[i]);
    }
    s.triangles = std::move(tris);
    s.triangle_material = std::move(materials);
    s.mesh_triangle_count *= 4;
  }
  s.normals = smooth_vertex_normals(s.positions, s.triangles);
  return s;
}

}  // namespace pt::bench
