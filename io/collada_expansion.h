// Counts what a visual scene expands to (node instances, vertices,
// primitives) without building it. instance_node can reuse a subtree many
// times over, so a few kilobytes can describe billions of triangles; the
// loader refuses such a file before it allocates anything. Also the first
// walk of the node graph, so cycles and deep nesting are refused here.
#pragma once

#include <cstdint>

#include <pugixml.hpp>

#include "collada_document.h"
#include "collada_mesh.h"
#include "load_limits.h"

namespace pt {

/// Upper bounds of what visiting `visual_scene` adds (every light counted as
/// the triangles and vertices of an elliptical area light).
struct SceneExpansion {
  uint64_t instances = 0, vertices = 0, primitives = 0, lights = 0;
};

/// Throws InputError naming the element when the expansion exceeds `limits`,
/// nodes nest deeper than limits.max_node_depth, or a node instances itself.
SceneExpansion check_scene_expansion(ColladaDocument& doc, pugi::xml_node visual_scene, MeshCache& meshes,
                                     const LoadLimits& limits);

}  // namespace pt
