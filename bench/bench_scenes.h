// Scenes of the ray tracing benchmark: the public CS184 scenes reduced to
// their triangles (every tracer gets exactly the same triangles), and the
// large scaling scenes derived from CBbunny by midpoint subdivision.
#pragma once

#include <optional>
#include <string>

#include "kernels/scene/scene.h"

namespace pt::bench {

/// Directory of the public CS184 scenes (../shared/scenes/cs184 next to the source).
std::string shared_scene_dir();

/// Loads a public scene by file name and drops its spheres (the benchmark
/// compares triangle kernels). nullopt when the file is absent.
std::optional<Scene> load_triangle_scene(const std::string& file);

/// Every triangle split into four at its edge midpoints, `levels` times
/// (x4 triangles per level, same surface, shared vertices stay shared).
/// Materials, lights and camera are kept; normals are recomputed.
Scene subdivide_scene(const Scene& s, int levels);

}  // namespace pt::bench
