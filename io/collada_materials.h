// Turns <material> elements into the scene's materials: <material> ->
// <instance_effect> -> <effect>; CGL emission makes an emitter, a CGL mirror,
// glass, refraction or microfacet element that kind of material, otherwise
// the common profile's diffuse colour is a Lambertian albedo (and, in a
// Blender 2.80+ export, its emission colour an emitted radiance). Properties
// it does not model (textures, specular, ...) are named in warnings.
#pragma once

#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

#include <pugixml.hpp>

#include "collada_document.h"
#include "kernels/scene/scene.h"

namespace pt {

class MaterialTable {
 public:
  /// `blender_units`: the file is a Blender 2.80+ export (its common
  /// profile's emission colour is read).
  MaterialTable(ColladaDocument& doc, Scene& scene, bool blender_units = false)
      : doc_(doc), scene_(scene), blender_(blender_units) {}

  /// Scene material index for a <material> element, read once and cached.
  uint32_t get(pugi::xml_node material);
  /// The 0.5 grey Lambertian used where no material is bound.
  uint32_t fallback();
  /// "name: diffuse (r, g, b)[, emission (r, g, b)]" or the kind, for --scene-info.
  std::string describe(uint32_t index) const;

 private:
  Material read(pugi::xml_node material);
  void read_common(pugi::xml_node effect, Material& m);
  void read_scattering(pugi::xml_node cgl_material, Material& m);
  float3 fraction(pugi::xml_node parent, const char* name, float3 fallback);
  float index_of_refraction(pugi::xml_node parent);

  ColladaDocument& doc_;
  Scene& scene_;
  std::unordered_map<const void*, uint32_t> cache_;
  std::unordered_map<uint32_t, std::string> names_;
  int32_t fallback_ = -1;
  bool blender_ = false;
};

}  // namespace pt
