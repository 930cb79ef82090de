// The COLLADA loader proper: up axis, the visual scene's node tree and what
// its nodes instance (geometry, lights, camera, other nodes).
#include "collada_loader.h"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <unordered_map>
#include <unordered_set>

#include "blender_lights.h"
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

/// The Blender version in <asset><contributor><authoring_tool> ("Blender 3.4.1"), as major * 100 + minor, or 0.
int blender_version(pugi::xml_node root) {
  for (pugi::xml_node c : root.child("asset").children("contributor")) {
    std::string_view tool = c.child_value("authoring_tool");
    if (tool.substr(0, 8) != "Blender ") continue;
    int major = 0, minor = 0;
    if (std::sscanf(std::string(tool.substr(8, 16)).c_str(), "%d.%d", &major, &minor) == 2 && major >= 0 &&
        major < 1000 && minor >= 0 && minor < 100)
      return major * 100 + minor;
  }
  return 0;
}

class SceneReader {
 public:
  SceneReader(ColladaDocument& doc, Scene& scene, const LoadLimits& limits, std::vector<std::string>& contents)
      : doc_(doc),
        scene_(scene),
        limits_(limits),
        contents_(contents),
        blender_(blender_version(doc.root()) >= 280),
        materials_(doc, scene, blender_),
        meshes_(doc, blender_) {}

  void read() {
    contents_.push_back(blender_ ? "read as a Blender 2.80+ export: Blender's lights, camera and normals, Cycles' units"
                                 : "read as the CS184 course reads it");
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
    warn_unread_techniques();
    if (lights_placed_ > 0 && scene_.light_count() == 0)
      doc_.warn({}, "all " + std::to_string(lights_placed_) + " lights the scene places were skipped (see above); " +
                        (has_emitters() ? "only emissive materials light it" : "it renders black"));
    if (scene_.primitive_count() == 0) doc_.warn({}, "the scene has no geometry; it renders black");
    else if (scene_.light_count() == 0 && !has_emitters()) doc_.warn({}, "the scene has no lights; it renders black");
  }

 private:
  /// Names each <technique profile="..."> the loader does not read, once per
  /// profile (with the first one's line and how many there are).
  void warn_unread_techniques() {
    struct Unread {
      pugi::xml_node first;
      size_t count = 0;
    };
    std::vector<std::pair<std::string, Unread>> unread;
    std::vector<pugi::xml_node> stack{doc_.root()};
    bool blender_lights_misread = false;
    while (!stack.empty()) {
      pugi::xml_node n = stack.back();
      stack.pop_back();
      for (pugi::xml_node c = n.last_child(); c; c = c.previous_sibling())
        if (c.type() == pugi::node_element) stack.push_back(c);
      if (std::string_view(n.name()) != "technique" || !n.attribute("profile")) continue;
      std::string profile = n.attribute("profile").value();
      std::string_view owner = n.parent().parent().name();  // <owner><extra><technique>
      if (ColladaDocument::is_course_profile(profile)) continue;
      if (profile == "blender" && blender_ && (owner == "light" || owner == "camera")) continue;
      if (profile == "blender" && owner == "light" && n.child("type").attribute("type")) blender_lights_misread = true;
      auto it = std::find_if(unread.begin(), unread.end(), [&](const auto& u) { return u.first == profile; });
      if (it == unread.end()) it = unread.insert(unread.end(), {profile, Unread{n, 0}});
      ++it->second.count;
    }
    for (const auto& [profile, u] : unread)
      doc_.warn(u.first, "technique profile \"" + excerpt(profile) + "\" is not read (" + std::to_string(u.count) +
                             " in the file)" +
                             (profile == "blender" ? ": a file that does not say Blender 2.80 or later wrote it is "
                                                     "read as the course reads it"
                                                   : ""));
    if (blender_lights_misread)
      doc_.warn({},
                "its lights carry Blender 2.80+ parameters, but <authoring_tool> does not name Blender 2.80 or "
                "later: their colours are read as radiance (the course's reading), not as Blender's watts");
  }

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
        ++lights_placed_;
        std::string what =
            add_light(doc_, doc_.resolve(child, child.attribute("url").value()), world, scene_, blender_);
        if (!what.empty()) contents_.push_back(node_label(node) + what);
      } else if (kind == "instance_camera") {
        if (camera_found_) {
          doc_.warn(child, "more than one camera; using the first");
        } else {
          pugi::xml_node camera = doc_.resolve(child, child.attribute("url").value());
          scene_.camera = read_camera(doc_, camera, world, blender_);
          camera_found_ = true;
          char fov[64];
          std::snprintf(fov, sizeof fov, "%g", scene_.camera.hfov_deg);
          contents_.push_back(node_label(node) + "camera " + excerpt(camera.attribute("name").value()) +
                              (blender_ ? std::string(": at its node, sensor angle ") + fov +
                                              " degrees on the image's longer side (Blender's Auto fit)"
                                        : std::string(": the course's placement, xfov ") + fov + " degrees"));
        }
      } else if (kind == "instance_controller") {
        doc_.warn(child, "controllers (skinning, morphs) are not read; skipped");
      }
    }
    active_.erase(node.internal_object());
  }

  std::string node_label(pugi::xml_node node) const {
    const char* name = node.attribute("name") ? node.attribute("name").value() : node.attribute("id").value();
    return "node " + excerpt(*name ? name : "(unnamed)") + ": ";
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

  /// Blender's shading: a vertex per distinct (position, normal) corner, the
  /// normal transformed by the cofactor matrix (the inverse transpose times
  /// the determinant) and normalised. Returns "smooth", "flat" or "smooth and flat".
  std::string add_file_normals(pugi::xml_node inst, const MeshData& mesh, const std::vector<float3>& positions,
                               const Mat4& world) {
    float3 c0 = world.transform_vector({1, 0, 0}), c1 = world.transform_vector({0, 1, 0}),
           c2 = world.transform_vector({0, 0, 1});
    float3 k0 = cross(c1, c2), k1 = cross(c2, c0), k2 = cross(c0, c1);
    std::unordered_map<uint64_t, uint32_t> vertex_of;
    uint32_t base = static_cast<uint32_t>(scene_.positions.size());
    auto vertex = [&](uint32_t p, uint32_t n) {
      uint64_t key = (uint64_t(p) << 32) | n;
      auto [it, inserted] = vertex_of.emplace(key, base + static_cast<uint32_t>(vertex_of.size()));
      if (inserted) {
        float3 m = mesh.normals[n];
        float3 w = k0 * m.x + k1 * m.y + k2 * m.z;
        float len = length(w);
        if (!(len > 0.0f) || !std::isfinite(len)) doc_.fail(inst, "a transformed normal is degenerate");
        scene_.positions.push_back(positions[p]);
        scene_.normals.push_back(w / len);
      }
      return it->second;
    };
    bool smooth = false, flat = false;  // a flat face's corners share its one normal
    for (size_t i = 0; i < mesh.triangles.size(); ++i) {
      TriangleIndices t = mesh.triangles[i], n = mesh.normal_triangles[i];
      (n.v0 == n.v1 && n.v1 == n.v2 ? flat : smooth) = true;
      scene_.triangles.push_back({vertex(t.v0, n.v0), vertex(t.v1, n.v1), vertex(t.v2, n.v2)});
    }
    return smooth && flat ? "smooth and flat" : smooth ? "smooth" : "flat";
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
      std::string shading = "smooth (the course's vertex normals)";
      if (blender_ && !mesh.normal_triangles.empty()) {
        shading = add_file_normals(inst, mesh, positions, world) + " (the file's normals)";
      } else {
        std::vector<float3> normals = smooth_vertex_normals(positions, mesh.triangles);
        scene_.positions.insert(scene_.positions.end(), positions.begin(), positions.end());
        scene_.normals.insert(scene_.normals.end(), normals.begin(), normals.end());
        for (const TriangleIndices& t : mesh.triangles) {
          uint32_t b = static_cast<uint32_t>(base);
          scene_.triangles.push_back({t.v0 + b, t.v1 + b, t.v2 + b});
        }
      }
      for (size_t i = 0; i < mesh.triangles.size(); ++i)
        scene_.triangle_material.push_back(symbol_material[mesh.triangle_symbol[i]]);
      std::string materials;
      for (size_t i = 0; i < symbol_material.size(); ++i)
        materials += (i ? ", " : "") + materials_.describe(symbol_material[i]);
      contents_.push_back(node_label(inst.parent()) + "mesh " + excerpt(geometry.attribute("name").value()) + ", " +
                          std::to_string(mesh.triangles.size()) + " triangles, " + shading +
                          "; materials: " + (materials.empty() ? "none" : materials));
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
      char r[32];
      std::snprintf(r, sizeof r, "%g", s.radius);
      contents_.push_back(node_label(inst.parent()) + "sphere (CGL), radius " + r + "; material " +
                          materials_.describe(s.material));
    } else {
      pugi::xml_node kind = geometry.first_child();
      doc_.warn(geometry, "neither a <mesh> nor a CGL sphere" +
                              (kind ? " (<" + excerpt(kind.name()) + ">)" : std::string()) + "; skipped");
    }
  }

  ColladaDocument& doc_;
  Scene& scene_;
  const LoadLimits& limits_;
  std::vector<std::string>& contents_;
  bool blender_;  ///< a Blender 2.80+ export
  MaterialTable materials_;
  MeshCache meshes_;
  std::unordered_set<const void*> active_;
  bool camera_found_ = false;
  size_t lights_placed_ = 0;
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
  SceneReader(doc, r.scene, limits, r.contents).read();
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

std::string scene_info(const LoadResult& r) {
  std::string out = scene_summary(r) + "\n";
  for (const std::string& c : r.contents) out += "  " + c + "\n";
  out += r.warnings.empty() ? std::string("ignored: nothing\n")
                            : "ignored or changed (" + std::to_string(r.warnings.size()) + "):\n";
  for (const std::string& w : r.warnings) out += "  " + w + "\n";
  return out;
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
