// MaterialTable: effect resolution and the CGL material extras.
#include "collada_materials.h"

namespace pt {
namespace {

pugi::xml_node cgl_technique(pugi::xml_node parent) {
  for (pugi::xml_node t : parent.child("extra").children("technique"))
    if (std::string_view(t.attribute("profile").value()) == "CGL") return t;
  return {};
}

}  // namespace

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
  if (m.albedo.x < 0 || m.albedo.y < 0 || m.albedo.z < 0)
    doc_.fail(effect, "negative diffuse colour");
  if (max_component(m.albedo) > 1.0f) doc_.warn(effect, "diffuse albedo above 1 reflects more light than it receives");

  if (pugi::xml_node cgl = cgl_technique(effect)) {
    if (pugi::xml_node emission = cgl.child("emission")) {
      pugi::xml_node radiance = emission.child("radiance");
      if (!radiance) doc_.fail(emission, "has no <radiance>");
      m.emission = doc_.color(radiance);
      if (m.emission.x < 0 || m.emission.y < 0 || m.emission.z < 0) doc_.fail(radiance, "negative radiance");
      m.albedo = float3(0.0f);
    } else if (pugi::xml_node other = cgl.first_child()) {
      doc_.warn(material, "CGL <" + excerpt(other.name()) +
                              "> material is not supported; rendered as Lambertian with its diffuse colour");
    }
  }
  return m;
}

}  // namespace pt
