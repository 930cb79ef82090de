// Pre-splitting of triangles whose boxes are poor fits (long, thin and
// diagonal triangles) before the SAH build, after Karras and Aila (2013):
// each chosen triangle is cut at the coarsest planes of a power-of-two grid
// over the scene into fragments, each with the tight box of the triangle's
// part inside it. Fragments are ordinary build primitives that name their
// triangle, so a triangle may sit in several leaves (tighter boxes, fewer
// rays testing it for nothing) at a memory cost bounded by the budget. Off by
// default (Bvh4Options::presplit_budget = 0): measured, it helped some scenes
// and ray kinds and cost others as much (docs/what_was_tried.md).
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "kernels/math/bbox.h"

namespace pt {

/// The build primitives after pre-splitting: box, centre and the index (into
/// the caller's triangle list) of the triangle each one covers.
struct SplitReferences {
  std::vector<BBox> boxes;
  std::vector<float3> centers;
  std::vector<uint32_t> triangle;
};

/// Splits up to budget * n extra fragments off the n triangles (corners[3i ..
/// 3i + 2]), the most where the triangle's box has the most volume and the
/// coarsest grid planes cross it (flat axis-aligned triangles are never cut);
/// at most 64 cuts per triangle, so a larger budget is not all spent. Every
/// fragment box holds the part of its triangle inside its cell, clipped in
/// double precision, widened by a margin far above that arithmetic's rounding
/// and rounded outwards to float, never past the triangle's own box: the union
/// of a triangle's fragments covers it. budget = 0 returns one reference per
/// triangle with its plain box. Deterministic; parallel in the calling oneTBB
/// arena.
SplitReferences presplit_triangles(std::span<const float3> corners, float budget);

}  // namespace pt
