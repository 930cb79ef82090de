// The scene as this renderer reads it, written as JSON for other renderers
// (scripts/studies/peers/ builds it in Blender to render with Cycles): triangles with
// their smooth normals and materials, spheres, lights and the camera resolved
// for the output size, in world space (Y up). Nothing is re-derived from the
// .dae by the reader, so both renderers see the same scene.
#pragma once

#include <string>

#include "kernels/scene/camera.h"
#include "kernels/scene/scene.h"

namespace pt {

/// The JSON document of `scene` seen by `camera` at width x height pixels.
std::string scene_to_json(const Scene& scene, const Camera& camera, int width, int height);

}  // namespace pt
