// Read-only data every stage of a wave sees: the scene, its materials as SoA
// arrays for SIMD gathers, the camera and the settings, plus the light-sample
// layout that decides which random dimensions each light sample uses.
#pragma once

#include <cstdint>
#include <vector>

#include "kernels/simd/isa_namespace.h"
#include "kernels/scene/camera.h"
#include "kernels/transport/path_rules.h"
#include "kernels/render/render_settings.h"
#include "kernels/scene/scene.h"
#include "soa.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// Materials as SoA for gathers; one entry per scene material. The
/// parameters of the non-diffuse kinds (glass, microfacet, ...) are filled
/// only when the scene has a material of such a kind.
struct MaterialArrays {
  AlignedVector<float> albedo_r, albedo_g, albedo_b;
  AlignedVector<int32_t> emits;  ///< 1 if the material has emission
  AlignedVector<int32_t> kind;   ///< MaterialKind
  AlignedVector<float> ior, alpha, trans_r, trans_g, trans_b, eta_r, eta_g, eta_b, k_r, k_g, k_b;

  explicit MaterialArrays(const Scene& s);
  size_t bytes() const;
};

/// Triangle data as raw arrays for gathers. Never null: an empty scene points
/// at one zeroed dummy triangle so that masked-off gather lanes stay in bounds.
struct TriangleArrays {
  const int32_t* indices;                ///< 3 per triangle
  const float* positions;                ///< 3 per vertex
  const float* normals;                  ///< 3 per vertex
  const int32_t* material;               ///< 1 per triangle
  int32_t triangle_count, vertex_count;  ///< records of indices, of positions and normals

  explicit TriangleArrays(const Scene& s);
};

struct WaveContext {
  const Scene& scene;
  TriangleArrays triangles;
  const Camera& camera;
  const RenderSettings& settings;
  MaterialArrays materials;
  PathRules rules;
  uint32_t shadow_rays_per_vertex;  ///< upper bound, for queue sizes
  bool sky_visible;                 ///< escaped rays see the sky
  uint32_t material_kinds;          ///< Scene::material_kinds(): bit per kind present
  bool has_delta;                   ///< some material is a mirror, glass or refraction
  bool sort_by_material = true;     ///< WavefrontOptions::sort_by_material

  /// Whether every surface is diffuse (or an emitter): one shading kernel, no queues by material.
  bool diffuse_only() const { return material_kinds <= 1u; }

  WaveContext(const Scene& s, const Camera& c, const RenderSettings& rs);
};

}  // namespace PT_ISA_NS
}  // namespace pt::wf
