// Reads a <camera> and its node's placement into a CameraDescription:
// fields of view, clip distances, and the CS184 view direction
// d = normalise(node transform applied to the point (0, 0, -1)); or, in a
// Blender 2.80+ export, the camera where its node puts it, as Blender does.
#pragma once

#include <pugixml.hpp>

#include "collada_document.h"
#include "kernels/scene/scene.h"
#include "mat4.h"

namespace pt {

/// `blender_placement`: place the camera as Blender does (its node's origin,
/// looking along its -Z with +Y up) instead of by the course's rule.
CameraDescription read_camera(ColladaDocument& doc, pugi::xml_node camera, const Mat4& world,
                              bool blender_placement = false);

}  // namespace pt
