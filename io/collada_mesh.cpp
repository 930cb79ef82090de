// <mesh> reading: sources, <vertices>, and triangle / polygon index lists.
#include "collada_mesh.h"

#include <algorithm>
#include <cstring>

namespace pt {
namespace {

constexpr uint64_t kMaxCount = 1u << 30;  // any count attribute above this is a lie

uint64_t count_tokens(std::string_view text) {
  uint64_t n = 0;
  bool in_token = false;
  for (char c : text) {
    bool space = c == ' ' || c == '\n' || c == '\r' || c == '\t';
    if (!space && !in_token) ++n;
    in_token = !space;
  }
  return n;
}

/// Positions of the <source> a POSITION input names, through its accessor.
std::vector<float3> read_positions(ColladaDocument& doc, pugi::xml_node source) {
  if (std::strcmp(source.name(), "source") != 0) doc.fail(source, "expected a <source> of positions");
  pugi::xml_node array = source.child("float_array");
  if (!array) doc.fail(source, "has no <float_array>");
  std::vector<float> values = doc.floats(array);
  uint64_t declared = doc.count_attribute(array, "count", values.size(), kMaxCount);
  if (declared != values.size())
    doc.fail(array,
             "count=\"" + std::to_string(declared) + "\" but it holds " + std::to_string(values.size()) + " numbers");

  pugi::xml_node accessor = source.child("technique_common").child("accessor");
  uint64_t stride = 3, count = values.size() / 3, offset = 0;
  if (accessor) {
    stride = doc.count_attribute(accessor, "stride", 1, kMaxCount);
    offset = doc.count_attribute(accessor, "offset", 0, kMaxCount);
    if (stride < 3) doc.fail(accessor, "stride " + std::to_string(stride) + " is too small for 3D positions");
    count = doc.count_attribute(accessor, "count", 0, kMaxCount);
    if (count > 0 && offset + (count - 1) * stride + 3 > values.size())
      doc.fail(accessor, "count=\"" + std::to_string(count) + "\" reads past the end of its " +
                             std::to_string(values.size()) + "-number array");
  } else if (values.size() % 3 != 0) {
    doc.fail(array, "holds " + std::to_string(values.size()) + " numbers, not a multiple of 3");
  }
  std::vector<float3> positions(count);
  for (uint64_t i = 0; i < count; ++i) {
    const float* v = &values[offset + i * stride];
    positions[i] = {v[0], v[1], v[2]};
  }
  return positions;
}

struct PrimitiveLayout {
  uint64_t stride = 0;         // indices per corner
  uint64_t vertex_offset = 0;  // where the VERTEX index sits in a corner
  int64_t normal_offset = -1;  // where the NORMAL index sits, if any
  pugi::xml_node normal_input;
};

PrimitiveLayout read_layout(ColladaDocument& doc, pugi::xml_node prim) {
  PrimitiveLayout layout;
  bool has_vertex = false;
  for (pugi::xml_node input : prim.children("input")) {
    uint64_t offset = doc.count_attribute(input, "offset", 0, 1024);
    layout.stride = std::max(layout.stride, offset + 1);
    if (std::string_view(input.attribute("semantic").value()) == "VERTEX") {
      layout.vertex_offset = offset;
      has_vertex = true;
    } else if (std::string_view(input.attribute("semantic").value()) == "NORMAL" && !layout.normal_input) {
      layout.normal_offset = static_cast<int64_t>(offset);
      layout.normal_input = input;
    }
  }
  if (!has_vertex) doc.fail(prim, "has no <input semantic=\"VERTEX\">");
  return layout;
}

void append_polygons(ColladaDocument& doc, pugi::xml_node prim, const std::vector<uint32_t>& sizes, uint32_t symbol,
                     size_t vertex_count, bool read_normals, MeshData& mesh) {
  PrimitiveLayout layout = read_layout(doc, prim);
  if (!read_normals) layout.normal_input = {};
  pugi::xml_node p = prim.child("p");
  if (!p) doc.fail(prim, "has no <p> index list");
  std::vector<uint32_t> idx = doc.indices(p, UINT32_MAX, "index");
  uint64_t corners = 0;
  for (uint32_t n : sizes) corners += n;
  if (idx.size() != corners * layout.stride)
    doc.fail(p, "holds " + std::to_string(idx.size()) + " indices, but the primitive needs " +
                    std::to_string(corners * layout.stride) + " (" + std::to_string(corners) + " corners x " +
                    std::to_string(layout.stride) + " inputs)");
  auto vertex = [&](uint64_t corner) {
    uint32_t v = idx[corner * layout.stride + layout.vertex_offset];
    if (v >= vertex_count)
      doc.fail(
          p, "vertex index " + std::to_string(v) + " is out of range (" + std::to_string(vertex_count) + " positions)");
    return v;
  };
  // Normals: kept while every primitive so far has them (one source for the mesh).
  bool normals = layout.normal_input && mesh.normal_triangles.size() == mesh.triangles.size();
  if (normals) {
    if (mesh.normals.empty() && mesh.triangles.empty()) {
      mesh.normals =
          read_positions(doc, doc.resolve(layout.normal_input, layout.normal_input.attribute("source").value()));
    } else if (mesh.normals.empty()) {
      normals = false;
    }
  }
  if (!normals) {
    mesh.normals.clear();
    mesh.normal_triangles.clear();
  }
  auto normal = [&](uint64_t corner) {
    uint32_t v = idx[corner * layout.stride + static_cast<uint64_t>(layout.normal_offset)];
    if (v >= mesh.normals.size())
      doc.fail(p, "normal index " + std::to_string(v) + " is out of range (" + std::to_string(mesh.normals.size()) +
                      " normals)");
    return v;
  };
  uint64_t first = 0;
  for (uint32_t n : sizes) {
    if (n < 3) doc.fail(prim, "has a polygon with " + std::to_string(n) + " vertices");
    uint32_t v0 = vertex(first);
    for (uint32_t k = 1; k + 1 < n; ++k) {
      mesh.triangles.push_back({v0, vertex(first + k), vertex(first + k + 1)});
      mesh.triangle_symbol.push_back(symbol);
      if (normals) mesh.normal_triangles.push_back({normal(first), normal(first + k), normal(first + k + 1)});
    }
    first += n;
  }
}

}  // namespace

MeshData read_mesh(ColladaDocument& doc, pugi::xml_node mesh_node, bool normals) {
  MeshData mesh;
  pugi::xml_node vertices = mesh_node.child("vertices");
  if (!vertices) doc.fail(mesh_node, "has no <vertices>");
  pugi::xml_node position_input = vertices.find_child_by_attribute("input", "semantic", "POSITION");
  if (!position_input) doc.fail(vertices, "has no <input semantic=\"POSITION\">");
  mesh.positions = read_positions(doc, doc.resolve(position_input, position_input.attribute("source").value()));

  for (pugi::xml_node prim : mesh_node.children()) {
    std::string_view kind = prim.name();
    bool is_triangles = kind == "triangles", is_polylist = kind == "polylist";
    if (!is_triangles && !is_polylist) {
      if (kind == "polygons" || kind == "trifans" || kind == "tristrips" || kind == "lines" || kind == "linestrips")
        doc.warn(prim, "primitive type not supported; skipped");
      else if (kind != "source" && kind != "vertices" && kind != "extra")
        doc.warn(prim, "mesh element not read; skipped");
      continue;
    }
    uint32_t symbol = static_cast<uint32_t>(mesh.symbols.size());
    mesh.symbols.emplace_back(prim.attribute("material").value());
    if (!prim.child("p")) doc.fail(prim, "has no <p> index list");
    uint64_t count = doc.count_attribute(prim, "count", 0, kMaxCount);
    std::vector<uint32_t> sizes;
    if (is_triangles) {
      // Check the count against the index list before allocating anything by it.
      uint64_t needed = count * 3 * read_layout(doc, prim).stride;
      uint64_t available = count_tokens(prim.child("p").child_value());
      if (available != needed)
        doc.fail(prim, "count=\"" + std::to_string(count) + "\" needs " + std::to_string(needed) +
                           " indices but <p> holds " + std::to_string(available));
      sizes.assign(count, 3);
    } else {
      pugi::xml_node vcount = prim.child("vcount");
      if (!vcount) doc.fail(prim, "has no <vcount>");
      sizes = doc.indices(vcount, 1u << 16, "polygon size");
      if (sizes.size() != count)
        doc.fail(vcount,
                 "lists " + std::to_string(sizes.size()) + " polygons but count=\"" + std::to_string(count) + "\"");
    }
    append_polygons(doc, prim, sizes, symbol, mesh.positions.size(), normals, mesh);
  }
  return mesh;
}

const MeshData& MeshCache::get(pugi::xml_node mesh) {
  auto it = meshes_.find(mesh.internal_object());
  if (it == meshes_.end()) it = meshes_.emplace(mesh.internal_object(), read_mesh(doc_, mesh, normals_)).first;
  return it->second;
}

std::optional<float> read_sphere_radius(ColladaDocument& doc, pugi::xml_node geometry) {
  for (pugi::xml_node tech : geometry.child("extra").children("technique")) {
    if (!ColladaDocument::is_course_profile(tech.attribute("profile").value())) continue;
    pugi::xml_node sphere = tech.child("sphere");
    if (!sphere) continue;
    pugi::xml_node radius = sphere.child("radius");
    if (!radius) doc.fail(sphere, "has no <radius>");
    float r = doc.scalar(radius, 0.0f);
    if (!(r > 0.0f)) doc.fail(radius, "sphere radius must be positive");
    return r;
  }
  return std::nullopt;
}

}  // namespace pt
