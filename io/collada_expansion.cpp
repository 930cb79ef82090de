// check_scene_expansion: a memoised walk of the node graph (a DAG once
// cycles are refused), so its cost is linear in the file however often
// subtrees are instanced. Sums saturate instead of overflowing.
#include "collada_expansion.h"

#include <limits>
#include <string>
#include <unordered_map>
#include <unordered_set>

namespace pt {
namespace {

uint64_t saturating_add(uint64_t a, uint64_t b) {
  return a > std::numeric_limits<uint64_t>::max() - b ? std::numeric_limits<uint64_t>::max() : a + b;
}

SceneExpansion& operator+=(SceneExpansion& a, const SceneExpansion& b) {
  a.instances = saturating_add(a.instances, b.instances);
  a.vertices = saturating_add(a.vertices, b.vertices);
  a.primitives = saturating_add(a.primitives, b.primitives);
  a.lights = saturating_add(a.lights, b.lights);
  return a;
}

class ExpansionCounter {
 public:
  ExpansionCounter(ColladaDocument& doc, MeshCache& meshes, const LoadLimits& limits)
      : doc_(doc), meshes_(meshes), limits_(limits) {}

  SceneExpansion node(pugi::xml_node node, int depth) {
    if (depth > limits_.max_node_depth)
      doc_.fail(node, "nodes nest deeper than " + std::to_string(limits_.max_node_depth) + " levels");
    if (auto it = done_.find(node.internal_object()); it != done_.end()) return it->second;
    if (!active_.insert(node.internal_object()).second) doc_.fail(node, "node instances itself (a cycle)");
    SceneExpansion e{1, 0, 0, 0};
    for (pugi::xml_node child : node.children()) {
      std::string_view kind = child.name();
      if (kind == "node") e += this->node(child, depth + 1);
      else if (kind == "instance_node") e += this->node(doc_.resolve(child, child.attribute("url").value()), depth + 1);
      else if (kind == "instance_geometry") e += geometry(child);
      else if (kind == "instance_light") e += SceneExpansion{1, kEllipseSegments + 1, kEllipseSegments, 1};
      else if (kind == "instance_camera") e += SceneExpansion{1, 0, 0, 0};
      check(child, e);
    }
    active_.erase(node.internal_object());
    done_.emplace(node.internal_object(), e);
    return e;
  }

  void check(pugi::xml_node where, const SceneExpansion& e) const {
    auto over = [&](uint64_t n, uint64_t limit, const char* what) {
      if (n > limit)
        doc_.fail(where, "the scene expands to more than " + std::to_string(limit) + " " + what +
                             " (counting every copy instance_node makes)");
    };
    over(e.instances, limits_.max_instances, "node instances");
    over(e.vertices, limits_.max_vertices, "vertices");
    over(e.primitives, limits_.max_primitives, "primitives");
    over(e.lights, limits_.max_lights, "lights");
  }

 private:
  SceneExpansion geometry(pugi::xml_node inst) {
    pugi::xml_node geometry = doc_.resolve(inst, inst.attribute("url").value());
    pugi::xml_node mesh = geometry.child("mesh");
    if (!mesh) return {1, 0, 1, 0};  // a sphere, or skipped
    const MeshData& m = meshes_.get(mesh);
    return {1, m.positions.size(), m.triangles.size(), 0};
  }

  ColladaDocument& doc_;
  MeshCache& meshes_;
  const LoadLimits& limits_;
  std::unordered_map<const void*, SceneExpansion> done_;
  std::unordered_set<const void*> active_;
};

}  // namespace

SceneExpansion check_scene_expansion(ColladaDocument& doc, pugi::xml_node visual_scene, MeshCache& meshes,
                                     const LoadLimits& limits) {
  ExpansionCounter counter(doc, meshes, limits);
  SceneExpansion total;
  for (pugi::xml_node node : visual_scene.children("node")) {
    total += counter.node(node, 1);
    counter.check(node, total);
  }
  return total;
}

}  // namespace pt
