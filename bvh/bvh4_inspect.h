// Looking into the 4-wide BVH for the live view's overlays: the boxes of the
// child slots at one depth, and the walk of one ray, the inner nodes a
// closest-hit traversal tests and the leaves it opens, in order. The walk
// applies the traversal's rules (children nearest entry first, one hit child
// descended without the stack, subtrees popped only while their entry is not
// beyond the nearest hit) in plain code compiled once, so it is an account of
// the traversal for display, not the fast path.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "bvh4.h"
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

/// The closest-hit walk of `ray` from the root. `fused`: the node test's
/// plane distances rounded once (x * y - z fused, as levels with FMA compute
/// them) or twice, so that ties and prunes fall as in the engine's level.
Bvh4Walk walk_bvh4(const Bvh4& bvh, const Ray& ray, bool fused, size_t max_visits);

}  // namespace pt
