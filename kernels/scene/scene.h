// The scene model: only what rendering needs, as flat arrays in world space
// (Y up). Loaders fill it; BVH builders, both renderers and the benchmarks read
// it. No scene graph survives loading.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/bbox.h"
#include "kernels/scene/environment_map.h"
#include "kernels/scene/lights.h"
#include "kernels/math/vec3.h"

namespace pt {

/// 12 bytes: vertex indices of one triangle.
struct TriangleIndices {
  uint32_t v0, v1, v2;
};
static_assert(sizeof(TriangleIndices) == 12);

/// How a material scatters light (docs/rendering.md).
enum class MaterialKind : uint32_t {
  kDiffuse,     ///< Lambertian: albedo / pi (emitters are diffuse with black albedo)
  kMirror,      ///< perfect specular reflection, scaled by albedo (reflectance)
  kGlass,       ///< smooth dielectric: Fresnel-weighted reflection (albedo) and refraction (transmittance)
  kRefraction,  ///< smooth dielectric, refraction only (transmittance)
  kMicrofacet,  ///< rough conductor: Beckmann distribution, Smith shadowing, conductor Fresnel (eta, k)
};
inline constexpr uint32_t kMaterialKindCount = 5;

inline namespace PT_ISA_NS {
/// Whether a kind scatters into a single direction (no light sampling).
constexpr bool is_delta(MaterialKind k) {
  return k == MaterialKind::kMirror || k == MaterialKind::kGlass || k == MaterialKind::kRefraction;
}
}  // namespace PT_ISA_NS

/// Smallest Beckmann roughness rendered (smaller values are raised to it):
/// keeps D(h) finite in float.
inline constexpr float kMinMicrofacetAlpha = 1e-4f;

/// 80 bytes. A reflector of one kind and/or an emitter.
struct Material {
  float3 albedo{0.5f};  ///< diffuse albedo; reflectance of mirror and glass
  float3 emission{0.0f};
  int32_t area_light = -1;  ///< area light whose geometry this is, or -1
  uint32_t flags = 0;       ///< kOneSided: emits only where the normal points
  MaterialKind kind = MaterialKind::kDiffuse;
  float ior = 1.0f;            ///< glass, refraction: inside index / outside index
  float alpha = 0.0f;          ///< microfacet: Beckmann roughness
  float3 transmittance{0.0f};  ///< glass, refraction
  float3 eta{0.0f}, k{0.0f};   ///< microfacet: conductor's complex index per RGB channel

  static constexpr uint32_t kOneSided = 1;
  bool is_emitter() const { return !is_black(emission); }
};
static_assert(sizeof(Material) == 80);

/// 20 bytes.
struct Sphere {
  float3 center;
  float radius;
  uint32_t material;
};
static_assert(sizeof(Sphere) == 20);

/// What the file says about the camera; resolved into a Camera for a given
/// output size by resolve_camera(). The course's rule (docs/cs184_compatibility.md)
/// places it by view_dir and widens hfov/vfov to the image; a Blender 2.80+
/// export's camera (`placed`) sits where its node puts it, and its hfov_deg is
/// the sensor width's angle, which Blender's Auto sensor fit gives the
/// image's longer side (docs/blender_scenes.md).
struct CameraDescription {
  float hfov_deg = 50.0f, vfov_deg = 35.0f;
  float near_clip = 0.01f, far_clip = 100.0f;
  float3 view_dir{0.0f, 0.0f, 1.0f};  ///< camera sits at centre + distance * view_dir
  bool placed = false;                ///< Blender's camera: the fields below
  float3 position{0.0f};
  float3 screen_x{1.0f, 0.0f, 0.0f}, screen_y{0.0f, 1.0f, 0.0f}, to_camera{0.0f, 0.0f, 1.0f};  ///< unit
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
  std::optional<SkyLight> sky;                        ///< set (black) when an environment map replaces it
  std::shared_ptr<const EnvironmentMap> environment;  ///< -e: lights and is seen in every direction

  CameraDescription camera;
  BBox bounds;  ///< of all triangles and spheres

  size_t light_count() const {
    return area_lights.size() + point_lights.size() + directional_lights.size() + (sky ? 1 : 0);
  }
  size_t primitive_count() const { return triangles.size() + spheres.size(); }
  /// Bit (1 << kind) set for each material kind some material has.
  uint32_t material_kinds() const {
    uint32_t bits = 0;
    for (const Material& m : materials) bits |= 1u << static_cast<uint32_t>(m.kind);
    return bits;
  }
  bool has_delta_lights_only() const {
    return area_lights.empty() && !sky && (!point_lights.empty() || !directional_lights.empty());
  }
};

inline namespace PT_ISA_NS {
/// Radiance a ray escaping the scene in unit direction d sees: the
/// environment map's, else the sky's (the scene must have one of them).
inline float3 sky_radiance(const Scene& s, const float3& d) {
  return s.environment ? s.environment->radiance(d) : sky_radiance(*s.sky, d);
}

/// Solid-angle pdf with which light sampling picks escape direction d.
inline float sky_pdf(const Scene& s, const float3& d) { return s.environment ? s.environment->pdf(d) : kInv2Pi; }
}  // namespace PT_ISA_NS

/// Makes `map` the scene's sky: it replaces the file's sky light, if any.
void set_environment(Scene& s, std::shared_ptr<const EnvironmentMap> map);

/// Recomputes bounds from triangles and spheres.
BBox compute_scene_bounds(const Scene& s);

/// Triangles that stand for an elliptical area light (a fan around its centre).
inline constexpr uint32_t kEllipseSegments = 64;

/// Appends the triangles that make area light `index` visible to rays (two
/// for a parallelogram, kEllipseSegments for an ellipse), with a one-sided
/// emitting material.
void add_area_light_geometry(Scene& s, uint32_t index);

/// Smooth vertex normals as the course renderer computes them: the sum of the
/// unnormalised face normals (cross products) of the faces sharing each vertex
/// index, normalised. Vertices whose faces are all degenerate get (0, 1, 0).
/// `triangles` index into `positions` (one mesh).
std::vector<float3> smooth_vertex_normals(std::span<const float3> positions,
                                          std::span<const TriangleIndices> triangles);

}  // namespace pt
