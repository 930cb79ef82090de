// Scene helpers that every loader and generator shares.
#include "kernels/scene/scene.h"

#include <cmath>
#include <numbers>
#include <utility>

namespace pt {

void set_environment(Scene& s, std::shared_ptr<const EnvironmentMap> map) {
  s.environment = std::move(map);
  s.sky = SkyLight{float3(0.0f)};
}

BBox compute_scene_bounds(const Scene& s) {
  BBox b;
  for (const TriangleIndices& t : s.triangles) {
    b.expand(s.positions[t.v0]);
    b.expand(s.positions[t.v1]);
    b.expand(s.positions[t.v2]);
  }
  for (const Sphere& sp : s.spheres) {
    b.expand(sp.center - float3(sp.radius));
    b.expand(sp.center + float3(sp.radius));
  }
  return b;
}

namespace {

/// The ellipse's stand-in for rays: a fan of kEllipseSegments triangles around
/// the centre whose rim vertices lie on the ellipse scaled by sqrt(2 pi / (N
/// sin(2 pi / N))), so that the polygon's area equals the ellipse's (the rim
/// lies within 0.02% of the ellipse's radius).
void add_ellipse_triangles(Scene& s, const AreaLight& l) {
  const uint32_t n = kEllipseSegments;
  const double step = 2.0 * std::numbers::pi / n;
  const float scale = static_cast<float>(0.5 * std::sqrt(2.0 * std::numbers::pi / (n * std::sin(step))));
  uint32_t base = static_cast<uint32_t>(s.positions.size());
  s.positions.push_back(l.position);
  for (uint32_t i = 0; i < n; ++i) {
    float c = static_cast<float>(std::cos(step * i)), sn = static_cast<float>(std::sin(step * i));
    s.positions.push_back(l.position + l.dim_x * (scale * c) + l.dim_y * (scale * sn));
  }
  for (uint32_t i = 0; i <= n; ++i) s.normals.push_back(l.direction);
  // Counter-clockwise from dim_x to dim_y has normal cross(dim_x, dim_y): wind to the emitting side.
  bool ccw = dot(cross(l.dim_x, l.dim_y), l.direction) > 0.0f;
  for (uint32_t i = 0; i < n; ++i) {
    uint32_t a = base + 1 + i, b = base + 1 + (i + 1) % n;
    s.triangles.push_back(ccw ? TriangleIndices{base, a, b} : TriangleIndices{base, b, a});
  }
}

}  // namespace

void add_area_light_geometry(Scene& s, uint32_t index) {
  const AreaLight& l = s.area_lights[index];
  if (l.shape == AreaShape::kEllipse) {
    add_ellipse_triangles(s, l);
  } else {
    float3 hx = l.dim_x * 0.5f, hy = l.dim_y * 0.5f;
    uint32_t base = static_cast<uint32_t>(s.positions.size());
    s.positions.push_back(l.position - hx - hy);
    s.positions.push_back(l.position + hx - hy);
    s.positions.push_back(l.position + hx + hy);
    s.positions.push_back(l.position - hx + hy);
    for (int i = 0; i < 4; ++i) s.normals.push_back(l.direction);

    // Wind both triangles so their geometric normal equals the emitting direction.
    bool flip = dot(cross(l.dim_x, l.dim_y), l.direction) > 0.0f;
    TriangleIndices a{base, base + 3, base + 2}, b{base, base + 2, base + 1};
    if (flip) {
      std::swap(a.v1, a.v2);
      std::swap(b.v1, b.v2);
    }
    s.triangles.push_back(a);
    s.triangles.push_back(b);
  }

  Material m;
  m.albedo = float3(0.0f);
  m.emission = l.radiance;
  m.area_light = static_cast<int32_t>(index);
  m.flags = Material::kOneSided;
  uint32_t material = static_cast<uint32_t>(s.materials.size());
  s.materials.push_back(m);
  s.triangle_material.resize(s.triangles.size(), material);
}

std::vector<float3> smooth_vertex_normals(std::span<const float3> positions,
                                          std::span<const TriangleIndices> triangles) {
  std::vector<float3> sum(positions.size());
  for (const TriangleIndices& t : triangles) {
    float3 n = cross(positions[t.v1] - positions[t.v0], positions[t.v2] - positions[t.v0]);
    sum[t.v0] += n;
    sum[t.v1] += n;
    sum[t.v2] += n;
  }
  for (float3& n : sum) {
    float len = length(n);
    n = (len > 0.0f && std::isfinite(len)) ? n / len : float3{0.0f, 1.0f, 0.0f};
  }
  return sum;
}

}  // namespace pt
