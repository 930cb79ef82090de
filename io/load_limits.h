// How large a scene the COLLADA loader accepts after instancing, and how
// deeply its nodes may nest. A file beyond these is refused with an
// InputError before the loader allocates anything for the scene.
#pragma once

#include <cstdint>

namespace pt {

/// The defaults are far above any CS184 scene (CBbunny: 28,588 primitives)
/// and keep a refused file's memory use small.
struct LoadLimits {
  uint64_t max_instances = uint64_t(1) << 20;  ///< nodes and instance_* elements reached
  uint64_t max_vertices = uint64_t(1) << 24;
  uint64_t max_primitives = uint64_t(1) << 24;  ///< triangles + spheres
  uint64_t max_lights = uint64_t(1) << 12;      ///< every light costs each shading point a sample
  int max_node_depth = 256;
};

}  // namespace pt
