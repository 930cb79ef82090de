// Reads one <geometry>: a <mesh> of <triangles> / <polylist> primitives into
// local-space positions and triangles (polygons fan-triangulated), or a CGL
// sphere's radius.
#pragma once

#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include <pugixml.hpp>

#include "collada_document.h"
#include "kernels/scene/scene.h"

namespace pt {

struct MeshData {
  std::vector<float3> positions;
  std::vector<TriangleIndices> triangles;
  std::vector<uint32_t> triangle_symbol;  ///< index into `symbols`, per triangle
  std::vector<std::string> symbols;       ///< each primitive's material="..." symbol
  /// The file's NORMAL input, when every primitive has one: normals and, per
  /// triangle, the normal index of each corner (the course ignores them;
  /// Blender's exports are shaded by them).
  std::vector<float3> normals;
  std::vector<TriangleIndices> normal_triangles;
};

/// Reads `<mesh>`; throws InputError naming the offending element. The
/// NORMAL inputs are read only with `normals` (the course ignores them).
MeshData read_mesh(ColladaDocument& doc, pugi::xml_node mesh, bool normals = false);

/// Reads each <mesh> once, however often it is instanced.
class MeshCache {
 public:
  explicit MeshCache(ColladaDocument& doc, bool normals = false) : doc_(doc), normals_(normals) {}
  /// read_mesh(mesh), cached; the reference stays valid for the cache's life.
  const MeshData& get(pugi::xml_node mesh);

 private:
  ColladaDocument& doc_;
  bool normals_;
  std::unordered_map<const void*, MeshData> meshes_;
};

/// The radius of a CGL sphere geometry, or nullopt if `geometry` is not one.
std::optional<float> read_sphere_radius(ColladaDocument& doc, pugi::xml_node geometry);

}  // namespace pt
