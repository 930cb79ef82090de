// Hit equality, the oracle's hits and the sphere mesh of the BVH4 suites.
#include "support/bvh4_support.h"

#include <cmath>
#include <cstdio>
#include <map>

namespace pt::test {

QueueArrays::QueueArrays(std::span<const Ray> rays) : n(rays.size()) {
  for (std::vector<float>& f : field) f.resize(n + 1, NAN);
  for (size_t i = 0; i < n; ++i) {
    const Ray& r = rays[i];
    const float f[8] = {r.org.x, r.org.y, r.org.z, r.tmin, r.dir.x, r.dir.y, r.dir.z, r.tmax};
    for (int k = 0; k < 8; ++k) field[k][i] = f[k];
  }
  t.assign(n + 1, kSentinelHit.t), u.assign(n + 1, kSentinelHit.u), v.assign(n + 1, kSentinelHit.v);
  prim.assign(n + 1, kSentinelHit.prim);
  blocked.assign(n + 1, kUnwritten);
}

std::vector<Hit> closest_hits(const SceneBvh2& oracle, const std::vector<Ray>& rays) {
  std::vector<Hit> hits(rays.size());
  uint64_t tests = 0;
  for (size_t i = 0; i < rays.size(); ++i) oracle.intersect(rays[i], hits[i], tests);
  return hits;
}

float scene_scale(const Scene& s) {
  return std::max(max_component(abs(s.bounds.lower)), max_component(abs(s.bounds.upper)));
}

::testing::AssertionResult same_closest_hit(const Hit& e, const Hit& a, float scale) {
  auto describe = [](const Hit& h) {
    char t[32];
    std::snprintf(t, sizeof t, "%.9g", h.t);
    return "{t " + std::string(t) + ", u " + std::to_string(h.u) + ", v " + std::to_string(h.v) + ", prim " +
           std::to_string(h.prim) + "}";
  };
  auto fail = [&] { return ::testing::AssertionFailure() << "expected " << describe(e) << ", got " << describe(a); };
  if (!e.valid() || !a.valid()) return e.valid() == a.valid() ? ::testing::AssertionSuccess() : fail();
  float t_max = std::max(std::fabs(e.t), std::fabs(a.t));
  if (e.prim == a.prim) {
    bool close = std::fabs(e.t - a.t) <= 1e-5f * std::max(t_max, scale) && std::fabs(e.u - a.u) <= 1e-4f &&
                 std::fabs(e.v - a.v) <= 1e-4f;
    return close ? ::testing::AssertionSuccess() : fail();
  }
  return std::fabs(e.t - a.t) <= 1e-6f * t_max ? ::testing::AssertionSuccess() : fail();
}

Scene tessellated_sphere(int levels, float3 c, float r) {
  Scene s;
  const float g = (1.0f + std::sqrt(5.0f)) / 2.0f;
  s.positions = {{-1, g, 0},  {1, g, 0},  {-1, -g, 0}, {1, -g, 0}, {0, -1, g},  {0, 1, g},
                 {0, -1, -g}, {0, 1, -g}, {g, 0, -1},  {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  s.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                 {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                 {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  for (float3& p : s.positions) p = normalize(p);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> midpoint;
    auto mid = [&](uint32_t a, uint32_t b) {
      auto key = std::minmax(a, b);
      auto [it, inserted] = midpoint.try_emplace(key, static_cast<uint32_t>(s.positions.size()));
      if (inserted) s.positions.push_back(normalize(s.positions[a] + s.positions[b]));
      return it->second;
    };
    std::vector<TriangleIndices> next;
    for (const TriangleIndices& t : s.triangles) {
      uint32_t ab = mid(t.v0, t.v1), bc = mid(t.v1, t.v2), ca = mid(t.v2, t.v0);
      next.insert(next.end(), {{t.v0, ab, ca}, {t.v1, bc, ab}, {t.v2, ca, bc}, {ab, bc, ca}});
    }
    s.triangles = std::move(next);
  }
  for (float3& p : s.positions) p = c + p * r;
  s.triangle_material.assign(s.triangles.size(), 0);
  s.materials.push_back(Material{});
  s.mesh_triangle_count = static_cast<uint32_t>(s.triangles.size());
  s.normals = smooth_vertex_normals(s.positions, s.triangles);
  s.bounds = compute_scene_bounds(s);
  return s;
}

}  // namespace pt::test
