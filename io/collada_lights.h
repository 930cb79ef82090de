// Reads a <light> placed by a node: CGL area lights, point, directional and
// ambient (sky) lights; spot lights are skipped with a warning.
#pragma once

#include <pugixml.hpp>

#include "collada_document.h"
#include "kernels/scene/scene.h"
#include "mat4.h"

namespace pt {

/// Adds the light to `scene` (area lights also as two emitting triangles).
void add_light(ColladaDocument& doc, pugi::xml_node light, const Mat4& world, Scene& scene);

}  // namespace pt
