// The scene model: only what rendering needs, as flat arrays in world space
// (Y up). Loaders fill it; BVH builders, both renderers and the benchmarks read
// it. No scene graph survives loading.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "bbox.h"
#include "lights.h"
#include "vec3.h"

namespace pt {

/// 12 bytes: vertex indices of one triangle.
struct TriangleIndices {
  uint32_t v0, v1, v2;
};
static_assert(sizeof(TriangleIndices) == 12);

/// 32 bytes. Lambertian reflector (BSDF = albedo / pi) and/or emitter.
struct Material {
  float3 albedo{0.5f};
  float3 emission{0.0f};
  int32_t area_light = -1;   ///< area light whose geometry this is, or -1
  uint32_t flags = 0;        ///< kOneSided: emits only where the normal points

  static constexpr uint32_t kOneSided = 1;
  bool is_emitter() const { return !is_black(emission); }
};
static_assert(sizeof(Material) == 32);

/// 20 bytes.
struct Sphere {
  float3 center;
  float radius;
  uint32_t material;
};
static_assert(sizeof(Sphere) == 20);

/// What the file says about the camera; resolved into a Camera for a given
/// output size by resolve_camera(). See README, "Camera".
struct CameraDescription {
  float hfov_deg = 50.0f, vfov_deg = 35.0f;
  float near_clip = 0.01f, far_clip = 100.0f;
  float3 view_dir{0.0f, 0.0f, 1.0f};  ///< camera sits at centre + distance * view_dir
};

struct Scene {
  std::string name;
  // Triangles: mesh triangles first, then two per area light.
  std::vector<float3> positions;
  std::vector<float3> normals;  ///< smooth per-vertex shading normals (unit)
  std::vector<TriangleIndices> triangles;
  std::vector<uint32_t> triangle_material;
  uint32_t mesh_triangle_count = 0;

  std::vector<Sphere> spheres;
  std::vector<Material> materials;

  std::vector<AreaLight> area_lights;
  std::vector<PointLight> point_lights;
  std::vector<DirectionalLight> directional_lights;
  std::optional<SkyLight> sky;

  CameraDescription camera;
  BBox bounds;  ///< of all triangles and spheres

  size_t light_count() const {
    return area_lights.size() + point_lights.size() + directional_lights.size() + (sky ? 1 : 0);
  }
  size_t primitive_count() const { return triangles.size() + spheres.size(); }
  bool has_delta_lights_only() const {
    return area_lights.empty() && !sky && (!point_lights.empty() || !directional_lights.empty());
  }
};

/// Recomputes bounds from triangles and spheres.
BBox compute_scene_bounds(const Scene& s);

/// Appends the two triangles (and four vertices) that make area light `index`
/// visible to rays, with a one-sided emitting material.
void add_area_light_geometry(Scene& s, uint32_t index);

/// Smooth vertex normals as the course renderer computes them: the sum of the
/// unnormalised face normals (cross products) of the faces sharing each vertex
/// index, normalised. Vertices whose faces are all degenerate get (0, 1, 0).
/// `triangles` index into `positions` (one mesh).
std::vector<float3> smooth_vertex_normals(std::span<const float3> positions,
                                          std::span<const TriangleIndices> triangles);

}  // namespace pt
