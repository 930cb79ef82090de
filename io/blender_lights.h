// Reads the lights of a Blender 2.80+ COLLADA export as Cycles renders them.
// Blender's exporter writes a light's power into technique_common's <color>
// and its real kind, size and shape into the `blender` technique (<type>,
// <energy>, <area_shape>, <area_size>, <spotsize>, ...); this reads the
// technique and converts power to what the scene model holds, by Cycles'
// rules (docs/blender_scenes.md).
#pragma once

#include <string>
#include <vector>

#include <pugixml.hpp>

#include "collada_document.h"
#include "kernels/scene/scene.h"
#include "mat4.h"

namespace pt {

/// The `blender` technique of an element's <extra>, or an empty node.
pugi::xml_node blender_technique(pugi::xml_node element);

/// Adds the light that `light` describes, placed by `world` (Y up), to
/// `scene`, and returns a one-line description of what it became (for
/// --scene-info). Throws InputError naming the element for an unknown type,
/// a negative or non-finite energy or colour, or a size, radius or angle out
/// of range; names parameters it cannot render as Cycles does in warnings.
std::string add_blender_light(ColladaDocument& doc, pugi::xml_node light, const Mat4& world, Scene& scene);

}  // namespace pt
