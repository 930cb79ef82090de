// Scenes and cameras built in code for the light-transport tests, whose
// answers are known in closed form: quads with chosen shading normals, closed
// inward-facing boxes (of plain emitters or of area lights), and pinhole
// cameras aimed exactly where a test needs them. Also the settings every
// engine-level test starts from.
#pragma once

#include <cstdint>

#include "kernels/scene/camera.h"
#include "kernels/render/render_settings.h"
#include "kernels/scene/scene.h"

namespace pt::test {

/// Appends a material and returns its index.
uint32_t add_material(Scene& s, float3 albedo, float3 emission = float3{});

/// Appends the quad a, b, c, d (a parallelogram, corners in order) as two
/// triangles with its own four vertices, all carrying shading normal `normal`,
/// wound so that the geometric normal lies on the side of `normal`.
void add_quad(Scene& s, float3 a, float3 b, float3 c, float3 d, float3 normal, uint32_t material);

/// Appends the parallelogram corner + s e1 + t e2 (s, t in [0, 1]) with
/// shading normal e1 x e2 (normalised).
void add_parallelogram(Scene& s, float3 corner, float3 e1, float3 e2, uint32_t material);

/// Appends an area light (and its two emitting triangles) centred at `centre`
/// with edges dim_x, dim_y, emitting `radiance` towards `direction` (unit).
void add_area_light(Scene& s, float3 centre, float3 dim_x, float3 dim_y, float3 direction, float3 radiance);

/// The six faces of the axis-aligned box [lower, upper] as quads whose shading
/// normals point into the box (the faces share no vertices).
void add_inward_box(Scene& s, const BBox& box, uint32_t material);

/// Six area lights covering the faces of the cube [-h, h]^3, each emitting
/// `radiance` into the cube, whose triangles reflect with `albedo`.
void add_area_light_box(Scene& s, float h, float3 albedo, float3 radiance);

/// Sets mesh_triangle_count (when no area-light triangles were added) and bounds.
void finish_scene(Scene& s);

/// Pinhole camera at `eye` looking at `target` with +Y (or +Z when looking
/// along Y) as up; tan_half_h/v are the tangents of the half fields of view.
Camera look_at(float3 eye, float3 target, float tan_half_h, float tan_half_v, float far_clip = 1e30f);

/// The unit direction of the centre of pixel (x, y) (top-left origin) of a
/// width x height image, as camera_ray_direction computes it.
float3 pixel_center_direction(const Camera& c, int width, int height, int x, int y);

/// width x height, `spp` samples everywhere (adaptive sampling off), two
/// threads, seed 1, maximum depth 1.
RenderSettings fixed_settings(int width, int height, int spp);

}  // namespace pt::test
