// Reads a <light> placed by a node: CGL area lights, point, directional and
// ambient (sky) lights as the course reads them (spot lights are skipped with
// a warning); in a Blender 2.80+ export, Blender's lights as Cycles renders
// them (blender_lights.h).
#pragma once

#include <string>

#include <pugixml.hpp>

#include "collada_document.h"
#include "kernels/scene/scene.h"
#include "mat4.h"

namespace pt {

/// Adds the light to `scene` (area lights also as emitting triangles, once
/// the loader calls add_area_light_geometry); `blender_units`: the file is a
/// Blender 2.80+ export, whose light colours are powers. Returns one line
/// saying what the light became, or "" if it was skipped (with a warning).
std::string add_light(ColladaDocument& doc, pugi::xml_node light, const Mat4& world, Scene& scene, bool blender_units);

}  // namespace pt
