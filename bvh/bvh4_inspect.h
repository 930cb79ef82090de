// Looking into the 4-wide BVH for the live view's overlays: the boxes of the
// child slots at one depth, and the walk of one ray, the inner nodes a
// closest-hit traversal tests and the leaves it opens, in order. The walk is
// the renderer's own (bvh4_ray_walk.h, at the level the BVH's queries run
// at), which reports each node and leaf it takes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bvh4.h"
#include "scene_bvh4.h"
#include "kernels/math/bbox.h"
#include "kernels/math/ray.h"

namespace pt {

/// Child slots at one depth of the tree.
struct Bvh4Level {
  std::vector<BBox> boxes;  ///< at most the asked maximum, in depth-first order
  bool truncated = false;   ///< more slots lie at this depth than were returned
};

/// Depth 0 is the root's box (the union of its children); depth d >= 1 the
/// boxes of the children of the inner nodes at depth d - 1. A leaf ends its
/// branch. An empty tree has no boxes at any depth.
Bvh4Level bvh4_level(const Bvh4& bvh, int depth, size_t max_boxes);

/// The deepest depth that holds a box (0 for a single leaf; -1 when empty).
int bvh4_max_depth(const Bvh4& bvh);

/// 32 bytes. One step of a walk: an inner node whose children were tested, or
/// a leaf whose triangles were.
struct Bvh4Visit {
  BBox box;            ///< the node's slot in its parent (the root: the union of its children)
  uint32_t depth = 0;  ///< 0 for the root
  uint32_t leaf = 0;   ///< 1 for a leaf
};
static_assert(sizeof(Bvh4Visit) == 32);

struct Bvh4Walk {
  std::vector<Bvh4Visit> visits;  ///< in walk order; at most the asked maximum
  uint64_t inner_nodes = 0;       ///< inner nodes tested (TraversalCounters::nodes counts the same)
  uint64_t leaves = 0;            ///< leaves tested
  Hit hit;                        ///< nearest triangle hit (prim kInvalidId: none)
};

/// The closest-hit walk of `ray` from the root of `bvh`'s tree (its
/// triangles; spheres are not in the tree), as its queries walk it.
Bvh4Walk walk_bvh4(const SceneBvh4& bvh, const Ray& ray, size_t max_visits);

}  // namespace pt
