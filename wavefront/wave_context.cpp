// WaveContext setup.
#include "kernels/simd/isa_namespace.h"
#include "wave_context.h"

#include <algorithm>

#include "kernels/transport/shading.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

MaterialArrays::MaterialArrays(const Scene& s) {
  const bool other_kinds = s.material_kinds() > 1u;
  for (const Material& m : s.materials) {
    albedo_r.push_back(m.albedo.x);
    albedo_g.push_back(m.albedo.y);
    albedo_b.push_back(m.albedo.z);
    emits.push_back(m.is_emitter() ? 1 : 0);
    kind.push_back(static_cast<int32_t>(m.kind));
    if (!other_kinds) continue;
    ior.push_back(m.ior);
    alpha.push_back(m.alpha);
    trans_r.push_back(m.transmittance.x);
    trans_g.push_back(m.transmittance.y);
    trans_b.push_back(m.transmittance.z);
    eta_r.push_back(m.eta.x);
    eta_g.push_back(m.eta.y);
    eta_b.push_back(m.eta.z);
    k_r.push_back(m.k.x);
    k_g.push_back(m.k.y);
    k_b.push_back(m.k.z);
  }
  if (s.materials.empty()) {  // keep gathers in bounds for material 0
    albedo_r.push_back(0);
    albedo_g.push_back(0);
    albedo_b.push_back(0);
    emits.push_back(0);
    kind.push_back(0);
  }
}

size_t MaterialArrays::bytes() const {
  size_t b = (emits.capacity() + kind.capacity()) * sizeof(int32_t);
  for (const AlignedVector<float>* v : {&albedo_r, &albedo_g, &albedo_b, &ior, &alpha, &trans_r, &trans_g, &trans_b,
                                        &eta_r, &eta_g, &eta_b, &k_r, &k_g, &k_b})
    b += v->capacity() * sizeof(float);
  return b;
}

TriangleArrays::TriangleArrays(const Scene& s) {
  static const int32_t kZeroIndices[4] = {0, 0, 0, 0};
  static const float kZeroFloats[4] = {0, 0, 0, 0};
  bool empty = s.triangles.empty();
  indices = empty ? kZeroIndices : reinterpret_cast<const int32_t*>(s.triangles.data());
  positions = empty ? kZeroFloats : &s.positions.data()->x;
  normals = empty ? kZeroFloats : &s.normals.data()->x;
  material = empty ? kZeroIndices : reinterpret_cast<const int32_t*>(s.triangle_material.data());
  triangle_count = empty ? 1 : static_cast<int32_t>(s.triangles.size());
  vertex_count = empty ? 1 : static_cast<int32_t>(std::min(s.positions.size(), s.normals.size()));
}

WaveContext::WaveContext(const Scene& s, const Camera& c, const RenderSettings& rs)
    : scene(s),
      triangles(s),
      camera(c),
      settings(rs),
      materials(s),
      rules(s, rs),
      sky_visible(sky_is_visible(s, rs)),
      material_kinds(s.material_kinds()),
      has_delta((material_kinds & ((1u << uint32_t(MaterialKind::kMirror)) | (1u << uint32_t(MaterialKind::kGlass)) |
                                   (1u << uint32_t(MaterialKind::kRefraction)))) != 0) {
  if (rs.direct_by_hitting()) {
    shadow_rays_per_vertex = hemisphere_sample_count(s, rs);
  } else {
    size_t sampled = (s.area_lights.size() + (s.sky ? 1 : 0)) * static_cast<size_t>(rs.light_samples);
    shadow_rays_per_vertex = static_cast<uint32_t>(sampled + s.point_lights.size() + s.directional_lights.size());
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
