// Scenes and cameras built in code for the stability tests: a diffuse floor
// under an area light of any size (at constant power) or under delta lights
// only, an area light seen head-on beside black background, a floor with
// degenerate triangles seen at grazing angles, and any scene scaled uniformly.
#pragma once

#include "kernels/scene/camera.h"
#include "kernels/scene/scene.h"
#include "support/scene_builders.h"  // add_material, add_area_light, finish_scene

namespace pt::test {

/// A 20 x 20 floor (y = 0, albedo 0.5) under a square area light of side
/// `side` at height 1 facing down, radiance power / side^2: the irradiance
/// below it barely changes with its size.
Scene floor_under_square_light(float side, float power = 1.0f);

/// The same floor lit only by a point light at height 1 and/or a directional light.
Scene floor_under_delta_lights(bool point, bool directional);

/// A 2 x 2 area light 2 units in front of the camera (camera_facing_minus_z),
/// facing it, radiance 3; black background around it and a lit floor below.
Scene light_seen_head_on();

/// A floor under an area light with degenerate triangles on it: three equal
/// vertices, three collinear vertices, a needle 1e-7 wide, and zero-length
/// vertex normals on a regular triangle.
Scene floor_with_degenerate_triangles();

/// `scene` with every length multiplied by `k`: positions, spheres, lights,
/// the area lights' areas and the camera's clip distances (radiance unchanged).
Scene scaled_scene(const Scene& scene, float k);

/// Camera at height 0.5 above the floor's centre, looking straight down.
Camera camera_above_floor();

/// Camera at the origin looking along -Z with a 90 degree field of view.
Camera camera_facing_minus_z();

/// Camera 1e-4 above the floor looking along it, almost horizontally.
Camera camera_grazing_floor();

}  // namespace pt::test
