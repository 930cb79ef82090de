// WaveContext setup.
#include "wave_context.h"

#include "kernels/shading.h"

namespace pt::wf {

MaterialArrays::MaterialArrays(const Scene& s) {
  for (const Material& m : s.materials) {
    albedo_r.push_back(m.albedo.x);
    albedo_g.push_back(m.albedo.y);
    albedo_b.push_back(m.albedo.z);
    emits.push_back(m.is_emitter() ? 1 : 0);
  }
  if (s.materials.empty()) {  // keep gathers in bounds for material 0
    albedo_r.push_back(0); albedo_g.push_back(0); albedo_b.push_back(0); emits.push_back(0);
  }
}

TriangleArrays::TriangleArrays(const Scene& s) {
  static const int32_t kZeroIndices[4] = {0, 0, 0, 0};
  static const float kZeroFloats[4] = {0, 0, 0, 0};
  bool empty = s.triangles.empty();
  indices = empty ? kZeroIndices : reinterpret_cast<const int32_t*>(s.triangles.data());
  positions = empty ? kZeroFloats : &s.positions.data()->x;
  normals = empty ? kZeroFloats : &s.normals.data()->x;
  material = empty ? kZeroIndices : reinterpret_cast<const int32_t*>(s.triangle_material.data());
}

WaveContext::WaveContext(const Scene& s, const Camera& c, const RenderSettings& rs)
    : scene(s),
      triangles(s),
      camera(c),
      settings(rs),
      materials(s),
      rules(s, rs),
      sky_visible(s.sky && !rs.cs184_invisible_sky) {
  if (rs.direct_by_hitting()) {
    shadow_rays_per_vertex = hemisphere_sample_count(s, rs);
  } else {
    size_t sampled = (s.area_lights.size() + (s.sky ? 1 : 0)) * static_cast<size_t>(rs.light_samples);
    shadow_rays_per_vertex = static_cast<uint32_t>(sampled + s.point_lights.size() + s.directional_lights.size());
  }
}

}  // namespace pt::wf
