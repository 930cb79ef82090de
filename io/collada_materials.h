// Turns <material> elements into the scene's materials: <material> ->
// <instance_effect> -> <effect>; CGL emission makes an emitter, a CGL mirror,
// glass, refraction or microfacet element that kind of material, otherwise
// the common profile's diffuse colour is a Lambertian albedo.
#pragma once

#include <cstdint>
#include <unordered_map>

#include <pugixml.hpp>

#include "collada_document.h"
#include "kernels/scene/scene.h"

namespace pt {

class MaterialTable {
 public:
  MaterialTable(ColladaDocument& doc, Scene& scene) : doc_(doc), scene_(scene) {}

  /// Scene material index for a <material> element, read once and cached.
  uint32_t get(pugi::xml_node material);
  /// The 0.5 grey Lambertian used where no material is bound.
  uint32_t fallback();

 private:
  Material read(pugi::xml_node material);
  void read_scattering(pugi::xml_node cgl_material, Material& m);
  float3 fraction(pugi::xml_node parent, const char* name, float3 fallback);
  float index_of_refraction(pugi::xml_node parent);

  ColladaDocument& doc_;
  Scene& scene_;
  std::unordered_map<const void*, uint32_t> cache_;
  int32_t fallback_ = -1;
};

}  // namespace pt
