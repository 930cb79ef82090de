// MaterialTable: effect resolution and the CGL material extras.
#include "collada_materials.h"

#include <algorithm>
#include <utility>

namespace pt {
namespace {

pugi::xml_node cgl_technique(pugi::xml_node parent) {
  for (pugi::xml_node t : parent.child("extra").children("technique"))
    if (std::string_view(t.attribute("profile").value()) == "CGL") return t;
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
  return index;
}

Material MaterialTable::read(pugi::xml_node material) {
  if (std::string_view(material.name()) != "material") doc_.fail(material, "is not a <material>");
  pugi::xml_node instance = material.child("instance_effect");
  if (!instance) doc_.fail(material, "has no <instance_effect>");
  pugi::xml_node effect = doc_.resolve(instance, instance.attribute("url").value());

  Material m;
  pugi::xml_node common = effect.child("profile_COMMON").child("technique");
  for (const char* shader : {"phong", "lambert", "blinn", "constant"}) {
    pugi::xml_node color = common.child(shader).child("diffuse").child("color");
    if (color) {
      m.albedo = doc_.color(color);
      break;
    }
  }
  if (m.albedo.x < 0 || m.albedo.y < 0 || m.albedo.z < 0) doc_.fail(effect, "negative diffuse colour");
  if (max_component(m.albedo) > 1.0f) doc_.warn(effect, "diffuse albedo above 1 reflects more light than it receives");

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
