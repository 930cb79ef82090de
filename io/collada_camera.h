// Reads a <camera> and its node's placement into a CameraDescription:
// fields of view, clip distances, and the CS184 view direction
// d = normalise(node transform applied to the point (0, 0, -1)).
#pragma once

#include <pugixml.hpp>

#include "collada_document.h"
#include "kernels/scene/scene.h"
#include "mat4.h"

namespace pt {

CameraDescription read_camera(ColladaDocument& doc, pugi::xml_node camera, const Mat4& world);

}  // namespace pt
