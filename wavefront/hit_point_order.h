// A closest-hit queue and its hits reordered by the cell of each hit point:
// 8 x 8 x 8 cells over the scene's bounds, taken in Morton order, misses
// last, queue order kept within a cell (one counting-sort pass). Shading then
// walks neighbouring surface points together, so the shadow rays and the
// continuations it writes leave from neighbouring points: the queue tracer's
// streams keep their rays together for more levels, and the surface fetches
// share cache lines. A path has one ray in a queue and every random number
// is the path's own, so each path's sums keep their order: the image does
// not change (but for which of two triangles at exactly the same t a ray
// reports: the stream tracer's grouping of rays decides such ties).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/bbox.h"
#include "streams.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// The sort's scratch and the sorted queues (swapped with the sorted ones).
struct HitPointOrder {
  static constexpr uint32_t kCells = 8 * 8 * 8;  ///< bucket kCells: misses
  AlignedVector<uint32_t> cell, order;           ///< 8 bytes per ray
  RayQueue rays;                                 ///< 52 bytes per ray
  HitQueue hits;                                 ///< 16 bytes per ray

  size_t bytes() const { return (cell.capacity() + order.capacity()) * sizeof(uint32_t) + rays.bytes() + hits.bytes(); }
};

/// Reorders `rays` and `hits` (parallel, rays.size items) by the cell of
/// each hit point in `bounds` (the scene's; points outside go to the nearest
/// cell).
void sort_by_hit_point(const BBox& bounds, RayQueue& rays, HitQueue& hits, HitPointOrder& scratch);

}  // namespace PT_ISA_NS
}  // namespace pt::wf
