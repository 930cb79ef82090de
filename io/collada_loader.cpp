// The COLLADA loader proper: up axis, the visual scene's node tree and what
// its nodes instance (geometry, lights, camera, other nodes).
#include "collada_loader.h"

#include <cctype>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "collada_camera.h"
#include "collada_document.h"
#include "collada_expansion.h"
#include "collada_lights.h"
#include "collada_materials.h"
#include "collada_mesh.h"
#include "mat4.h"
#include "read_file.h"
#include "scene_error.h"

namespace pt {
namespace {

constexpr uint64_t kMaxFileBytes = uint64_t(1) << 31;

class SceneReader {
 public:
  SceneReader(ColladaDocument& doc, Scene& scene, const LoadLimits& limits)
      : doc_(doc), scene_(scene), limits_(limits), materials_(doc, scene), meshes_(doc) {}

  void read() {
    pugi::xml_node visual = visual_scene();
    if (visual) {
      check_scene_expansion(doc_, visual, meshes_, limits_);  // before anything is allocated by it
      Mat4 up = up_axis_transform();
      for (pugi::xml_node node : visual.children("node")) visit(node, up, 1);
    } else {
      doc_.warn(doc_.root(), "no <visual_scene>; the scene is empty");
    }
    scene_.mesh_triangle_count = static_cast<uint32_t>(scene_.triangles.size());
    for (uint32_t i = 0; i < scene_.area_lights.size(); ++i) add_area_light_geometry(scene_, i);
    scene_.bounds = compute_scene_bounds(scene_);
    if (scene_.primitive_count() == 0) doc_.warn({}, "the scene has no geometry; it renders black");
    else if (scene_.light_count() == 0 && !has_emitters()) doc_.warn({}, "the scene has no lights; it renders black");
  }

 private:
  bool has_emitters() const {
    for (const Material& m : scene_.materials)
      if (m.is_emitter()) return true;
    return false;
  }

  pugi::xml_node visual_scene() {
    pugi::xml_node inst = doc_.root().child("scene").child("instance_visual_scene");
    if (inst) return doc_.resolve(inst, inst.attribute("url").value());
    return doc_.root().child("library_visual_scenes").child("visual_scene");
  }

  Mat4 up_axis_transform() {
    pugi::xml_node up = doc_.root().child("asset").child("up_axis");
    std::string_view axis = up ? up.child_value() : "Y_UP";
    while (!axis.empty() && std::isspace(static_cast<unsigned char>(axis.back()))) axis.remove_suffix(1);
    while (!axis.empty() && std::isspace(static_cast<unsigned char>(axis.front()))) axis.remove_prefix(1);
    Mat4 m;
    if (axis == "Z_UP") {  // (x, y, z) -> (-x, z, y)
      m.m = {{{-1, 0, 0, 0}, {0, 0, 1, 0}, {0, 1, 0, 0}, {0, 0, 0, 1}}};
    } else if (axis == "X_UP") {  // (x, y, z) -> (y, x, -z)
      m.m = {{{0, 1, 0, 0}, {1, 0, 0, 0}, {0, 0, -1, 0}, {0, 0, 0, 1}}};
    } else {
      if (axis != "Y_UP") doc_.warn(up, "unknown up axis \"" + excerpt(axis) + "\"; using Y_UP");
      m = Mat4::identity();
    }
    return m;
  }

  Mat4 read_matrix(pugi::xml_node e) {
    std::vector<float> v = doc_.floats(e);
    if (v.size() > 16 || v.size() < 12) doc_.fail(e, "holds " + std::to_string(v.size()) + " numbers, expected 16");
    Mat4 m = Mat4::identity();
    if (v.size() < 16)
      doc_.warn(e, "holds " + std::to_string(v.size()) + " numbers, expected 16; the rest taken from the identity");
    for (size_t i = 0; i < v.size(); ++i) m.m[i / 4][i % 4] = v[i];
    return m;
  }

  Mat4 local_transform(pugi::xml_node node) {
    Mat4 m = Mat4::identity();
    for (pugi::xml_node e : node.children()) {
      std::string_view kind = e.name();
      if (kind == "matrix") {
        m = m * read_matrix(e);
      } else if (kind == "translate") {
        std::vector<float> v = doc_.floats(e, 3);
        m = m * Mat4::translation({v[0], v[1], v[2]});
      } else if (kind == "scale") {
        std::vector<float> v = doc_.floats(e, 3);
        m = m * Mat4::scaling({v[0], v[1], v[2]});
      } else if (kind == "rotate") {
        std::vector<float> v = doc_.floats(e, 4);
        m = m * Mat4::rotation({v[0], v[1], v[2]}, v[3]);
      } else if (kind == "lookat" || kind == "skew") {
        doc_.warn(e, "transform element not supported; ignored");
      }
    }
    if (!m.is_finite()) doc_.fail(node, "transform overflows to a non-finite matrix");
    return m;
  }

  void visit(pugi::xml_node node, const Mat4& parent, int depth) {
    // check_scene_expansion() has refused cycles and deep nesting; these guard the recursion regardless.
    if (depth > limits_.max_node_depth) doc_.fail(node, "nodes nest deeper than the limit");
    if (!active_.insert(node.internal_object()).second) doc_.fail(node, "node instances itself (a cycle)");
    Mat4 world = parent * local_transform(node);
    for (pugi::xml_node child : node.children()) {
      std::string_view kind = child.name();
      if (kind == "node") {
        visit(child, world, depth + 1);
      } else if (kind == "instance_node") {
        visit(doc_.resolve(child, child.attribute("url").value()), world, depth + 1);
      } else if (kind == "instance_geometry") {
        instance_geometry(child, world);
      } else if (kind == "instance_light") {
        add_light(doc_, doc_.resolve(child, child.attribute("url").value()), world, scene_);
      } else if (kind == "instance_camera") {
        if (camera_found_) {
          doc_.warn(child, "more than one camera; using the first");
        } else {
          scene_.camera = read_camera(doc_, doc_.resolve(child, child.attribute("url").value()), world);
          camera_found_ = true;
        }
      }
    }
    active_.erase(node.internal_object());
  }

  /// symbol -> <material> element, from the instance's bind_material.
  std::unordered_map<std::string, pugi::xml_node> bindings(pugi::xml_node inst) {
    std::unordered_map<std::string, pugi::xml_node> out;
    for (pugi::xml_node im : inst.child("bind_material").child("technique_common").children("instance_material"))
      out.emplace(im.attribute("symbol").value(), doc_.resolve(im, im.attribute("target").value()));
    return out;
  }

  uint32_t material_for_symbol(pugi::xml_node inst, const std::string& symbol,
                               const std::unordered_map<std::string, pugi::xml_node>& bound) {
    auto it = bound.find(symbol);
    if (it != bound.end()) return materials_.get(it->second);
    if (symbol.empty()) return bound.size() == 1 ? materials_.get(bound.begin()->second) : materials_.fallback();
    pugi::xml_node direct = doc_.find(symbol);
    if (direct && std::string_view(direct.name()) == "material") return materials_.get(direct);
    doc_.warn(inst, "material \"" + excerpt(symbol) + "\" is not bound; using grey");
    return materials_.fallback();
  }

  void instance_geometry(pugi::xml_node inst, const Mat4& world) {
    pugi::xml_node geometry = doc_.resolve(inst, inst.attribute("url").value());
    auto bound = bindings(inst);
    if (pugi::xml_node mesh_node = geometry.child("mesh")) {
      const MeshData& mesh = meshes_.get(mesh_node);
      uint64_t base = scene_.positions.size();
      std::vector<uint32_t> symbol_material(mesh.symbols.size());
      for (size_t i = 0; i < mesh.symbols.size(); ++i)
        symbol_material[i] = material_for_symbol(inst, mesh.symbols[i], bound);
      std::vector<float3> positions(mesh.positions.size());
      for (size_t i = 0; i < positions.size(); ++i) {
        positions[i] = world.transform_point(mesh.positions[i]);
        if (!within_coordinate_limit(positions[i]))
          doc_.fail(inst, "a transformed vertex position is not finite or exceeds the coordinate limit 1e15");
      }
      std::vector<float3> normals = smooth_vertex_normals(positions, mesh.triangles);
      scene_.positions.insert(scene_.positions.end(), positions.begin(), positions.end());
      scene_.normals.insert(scene_.normals.end(), normals.begin(), normals.end());
      for (size_t i = 0; i < mesh.triangles.size(); ++i) {
        TriangleIndices t = mesh.triangles[i];
        uint32_t b = static_cast<uint32_t>(base);
        scene_.triangles.push_back({t.v0 + b, t.v1 + b, t.v2 + b});
        scene_.triangle_material.push_back(symbol_material[mesh.triangle_symbol[i]]);
      }
    } else if (std::optional<float> radius = read_sphere_radius(doc_, geometry)) {
      Sphere s;
      s.center = world.transform_point({0, 0, 0});
      s.radius = *radius * length(world.transform_vector({1, 0, 0}));
      if (!(s.radius > 0.0f) || !within_coordinate_limit(s.center + float3(s.radius)) ||
          !within_coordinate_limit(s.center - float3(s.radius)))
        doc_.fail(inst, "sphere transform gives a degenerate sphere or one beyond the coordinate limit 1e15");
      // A sphere binds one material: the first <instance_material> in file order.
      pugi::xml_node first = inst.child("bind_material").child("technique_common").child("instance_material");
      s.material =
          first ? materials_.get(doc_.resolve(first, first.attribute("target").value())) : materials_.fallback();
      scene_.spheres.push_back(s);
    } else {
      doc_.warn(geometry, "neither a <mesh> nor a CGL sphere; skipped");
    }
  }

  ColladaDocument& doc_;
  Scene& scene_;
  const LoadLimits& limits_;
  MaterialTable materials_;
  MeshCache meshes_;
  std::unordered_set<const void*> active_;
  bool camera_found_ = false;
};

/// The arrays were grown element by element: keep no slack for the render.
void shrink_to_fit(Scene& s) {
  s.positions.shrink_to_fit();
  s.normals.shrink_to_fit();
  s.triangles.shrink_to_fit();
  s.triangle_material.shrink_to_fit();
  s.spheres.shrink_to_fit();
  s.materials.shrink_to_fit();
  s.area_lights.shrink_to_fit();
  s.point_lights.shrink_to_fit();
  s.directional_lights.shrink_to_fit();
}

/// Loads from `text`, which the document takes over (it keeps it for line numbers in messages).
LoadResult load_collada_text(std::string text, const std::string& label, const LoadLimits& limits) {
  auto start = std::chrono::steady_clock::now();
  LoadResult r;
  ColladaDocument doc(label, std::move(text));
  r.scene.name = label;
  SceneReader(doc, r.scene, limits).read();
  shrink_to_fit(r.scene);
  r.warnings = doc.warnings();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace

LoadResult load_collada_string(std::string_view xml, const std::string& label, const LoadLimits& limits) {
  return load_collada_text(std::string(xml), label, limits);
}

LoadResult load_collada_file(const std::filesystem::path& path, const LoadLimits& limits) {
  auto start = std::chrono::steady_clock::now();
  LoadResult r = load_collada_text(read_regular_file(path, "scene file", kMaxFileBytes), path.string(), limits);
  r.scene.name = path.filename().string();
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

std::string scene_summary(const LoadResult& r) {
  const Scene& s = r.scene;
  char bounds[160] = "empty";
  if (!s.bounds.empty())
    std::snprintf(bounds, sizeof bounds, "(%.3g, %.3g, %.3g)..(%.3g, %.3g, %.3g)", s.bounds.lower.x, s.bounds.lower.y,
                  s.bounds.lower.z, s.bounds.upper.x, s.bounds.upper.y, s.bounds.upper.z);
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "%s: %u mesh + %zu area-light triangles, %zu spheres; lights: %zu area, %zu point, "
                "%zu directional, %d sky; bounds %s; loaded in %.3f s",
                s.name.c_str(), s.mesh_triangle_count, s.triangles.size() - s.mesh_triangle_count, s.spheres.size(),
                s.area_lights.size(), s.point_lights.size(), s.directional_lights.size(), s.sky ? 1 : 0, bounds,
                r.seconds);
  return buf;
}

}  // namespace pt
