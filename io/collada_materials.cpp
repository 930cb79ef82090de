// MaterialTable: effect resolution and the CGL material extras.
#include "collada_materials.h"

#include <algorithm>
#include <cstdio>
#include <utility>

namespace pt {
namespace {

pugi::xml_node cgl_technique(pugi::xml_node parent) {
  for (pugi::xml_node t : parent.child("extra").children("technique"))
    if (ColladaDocument::is_course_profile(t.attribute("profile").value())) return t;
  return {};
}

}  // namespace

/// A reflectance or transmittance colour: three numbers in [0, 1] (above 1
/// only with a warning, as for diffuse albedo).
float3 MaterialTable::fraction(pugi::xml_node parent, const char* name, float3 fallback) {
  pugi::xml_node e = parent.child(name);
  if (!e) return fallback;
  float3 c = doc_.color(e);
  if (c.x < 0 || c.y < 0 || c.z < 0) doc_.fail(e, "negative colour");
  if (max_component(c) > 1.0f) doc_.warn(e, "above 1: the surface returns more light than it receives");
  return c;
}

float MaterialTable::index_of_refraction(pugi::xml_node parent) {
  pugi::xml_node e = parent.child("ior");
  float ior = doc_.scalar(e, 1.5f);
  if (!(ior > 0.0f) || ior > 100.0f) doc_.fail(e ? e : parent, "index of refraction must be in (0, 100]");
  return ior;
}

void MaterialTable::read_scattering(pugi::xml_node cgl_material, Material& m) {
  std::string_view kind = cgl_material.name();
  auto warn_rough = [&] {
    pugi::xml_node r = cgl_material.child("roughness");
    if (doc_.scalar(r, 0.0f) != 0.0f)
      doc_.warn(r, "roughness is ignored: rendered as a smooth dielectric (as the course does)");
  };
  if (kind == "mirror") {
    m.kind = MaterialKind::kMirror;
    m.albedo = fraction(cgl_material, "reflectance", float3(1.0f));
  } else if (kind == "glass") {
    m.kind = MaterialKind::kGlass;
    m.albedo = fraction(cgl_material, "reflectance", float3(1.0f));
    m.transmittance = fraction(cgl_material, "transmittance", float3(1.0f));
    m.ior = index_of_refraction(cgl_material);
    warn_rough();
  } else if (kind == "refraction") {
    m.kind = MaterialKind::kRefraction;
    m.albedo = float3(0.0f);
    m.transmittance = fraction(cgl_material, "transmittance", float3(1.0f));
    m.ior = index_of_refraction(cgl_material);
    warn_rough();
  } else if (kind == "microfacet") {
    m.kind = MaterialKind::kMicrofacet;
    pugi::xml_node alpha = cgl_material.child("alpha");
    m.alpha = doc_.scalar(alpha, 0.5f);
    if (!(m.alpha > 0.0f) || m.alpha > 10.0f) doc_.fail(alpha ? alpha : cgl_material, "alpha must be in (0, 10]");
    m.alpha = std::max(m.alpha, kMinMicrofacetAlpha);
    for (auto [name, out] : {std::pair{"eta", &m.eta}, std::pair{"k", &m.k}}) {
      pugi::xml_node e = cgl_material.child(name);
      if (!e) doc_.fail(cgl_material, std::string("has no <") + name + ">");
      *out = doc_.color(e);
      if (!(out->x >= 0 && out->y >= 0 && out->z >= 0)) doc_.fail(e, "negative value");
    }
    for (int c = 0; c < 3; ++c)
      if (m.eta[c] == 0.0f && m.k[c] == 0.0f)
        doc_.fail(cgl_material.child("eta"), "eta and k are both zero in a channel");
    m.albedo = float3(0.0f);
  } else {
    doc_.warn(cgl_material, "CGL <" + excerpt(cgl_material.name()) +
                                "> material is not supported; rendered as Lambertian with its diffuse colour");
  }
}

namespace {

bool black_or_absent(ColladaDocument& doc, pugi::xml_node property) {
  pugi::xml_node c = property.child("color");
  if (!c) return !property.child("texture");
  float3 v = doc.color(c);
  return v.x == 0.0f && v.y == 0.0f && v.z == 0.0f;
}

}  // namespace

/// The common profile's shader: its diffuse colour (and, from Blender, its
/// emission); every other property that would change the image is named.
void MaterialTable::read_common(pugi::xml_node effect, Material& m) {
  for (pugi::xml_node p : effect.children()) {
    std::string_view kind = p.name();
    if (kind != "profile_COMMON" && kind != "extra" && kind != "asset" && kind != "annotate")
      doc_.warn(p, "effect profile not read (only profile_COMMON and the CGL technique are)");
  }
  pugi::xml_node common = effect.child("profile_COMMON").child("technique");
  pugi::xml_node shader;
  for (const char* name : {"phong", "lambert", "blinn", "constant"})
    if ((shader = common.child(name))) break;
  if (!shader) return;
  if (pugi::xml_node diffuse = shader.child("diffuse")) {
    if (pugi::xml_node color = diffuse.child("color")) m.albedo = doc_.color(color);
    else if (diffuse.child("texture"))
      doc_.warn(diffuse, "a texture is not modelled; rendered with the diffuse colour 0.5 grey");
  }
  if (m.albedo.x < 0 || m.albedo.y < 0 || m.albedo.z < 0) doc_.fail(effect, "negative diffuse colour");
  if (max_component(m.albedo) > 1.0f) doc_.warn(effect, "diffuse albedo above 1 reflects more light than it receives");
  for (pugi::xml_node p : shader.children()) {
    std::string_view kind = p.name();
    if (kind == "diffuse" || kind == "index_of_refraction") continue;  // an opaque surface's ior changes nothing
    if (kind == "emission" && blender_) {
      if (pugi::xml_node color = p.child("color")) {
        m.emission = doc_.color(color);
        if (m.emission.x < 0 || m.emission.y < 0 || m.emission.z < 0) doc_.fail(color, "negative emission colour");
        if (m.is_emitter())
          doc_.warn(p,
                    "emission colour read as radiance at strength 1: Blender's exporter drops the emission "
                    "strength (docs/blender_scenes.md)");
      } else if (p.child("texture")) {
        doc_.warn(p, "an emission texture is not modelled; no emission");
      }
      continue;
    }
    if (kind == "shininess" || kind == "transparency" || kind == "reflectivity") continue;  // named with their colour
    bool matters = kind == "transparent" ? true : !black_or_absent(doc_, p);
    if (kind == "reflective" && doc_.scalar(shader.child("reflectivity").child("float"), 1.0f) == 0.0f) matters = false;
    if (matters)
      doc_.warn(p, "<" + excerpt(shader.name()) + "> property not modelled (" +
                       (kind == "emission" ? "the course reads CGL emission only" : "rendered as Lambertian diffuse") +
                       ")");
  }
}

std::string MaterialTable::describe(uint32_t index) const {
  const Material& m = scene_.materials[index];
  auto it = names_.find(index);
  std::string name = it == names_.end() ? "(default grey)" : it->second;
  char b[160];
  static const char* kKinds[] = {"diffuse", "mirror", "glass", "refraction", "microfacet"};
  std::snprintf(b, sizeof b, " %s (%g, %g, %g)", kKinds[static_cast<uint32_t>(m.kind)], m.albedo.x, m.albedo.y,
                m.albedo.z);
  std::string out = name + b;
  if (m.is_emitter()) {
    std::snprintf(b, sizeof b, ", emission (%g, %g, %g)", m.emission.x, m.emission.y, m.emission.z);
    out += b;
  }
  return out;
}

uint32_t MaterialTable::fallback() {
  if (fallback_ < 0) {
    fallback_ = static_cast<int32_t>(scene_.materials.size());
    scene_.materials.push_back(Material{});
  }
  return static_cast<uint32_t>(fallback_);
}

uint32_t MaterialTable::get(pugi::xml_node material) {
  auto it = cache_.find(material.internal_object());
  if (it != cache_.end()) return it->second;
  uint32_t index = static_cast<uint32_t>(scene_.materials.size());
  scene_.materials.push_back(read(material));
  cache_.emplace(material.internal_object(), index);
  const char* name = material.attribute("name") ? material.attribute("name").value() : material.attribute("id").value();
  names_.emplace(index, excerpt(name));
  return index;
}

Material MaterialTable::read(pugi::xml_node material) {
  if (std::string_view(material.name()) != "material") doc_.fail(material, "is not a <material>");
  pugi::xml_node instance = material.child("instance_effect");
  if (!instance) doc_.fail(material, "has no <instance_effect>");
  pugi::xml_node effect = doc_.resolve(instance, instance.attribute("url").value());

  Material m;
  read_common(effect, m);

  if (pugi::xml_node cgl = cgl_technique(effect)) {
    if (pugi::xml_node emission = cgl.child("emission")) {
      pugi::xml_node radiance = emission.child("radiance");
      if (!radiance) doc_.fail(emission, "has no <radiance>");
      m.emission = doc_.color(radiance);
      if (m.emission.x < 0 || m.emission.y < 0 || m.emission.z < 0) doc_.fail(radiance, "negative radiance");
      m.albedo = float3(0.0f);
    } else if (pugi::xml_node other = cgl.first_child()) {
      read_scattering(other, m);
    }
  }
  return m;
}

}  // namespace pt
