// Collapse of a binary BVH into the 4-wide layout: every 4-wide node adopts
// the children of its largest-area inner children until it has four (as
// tinybvh and Embree's BVH4 builders do). Knows nothing about triangles: it
// returns, per leaf block lane, which input primitive goes there.
#pragma once

#include <cstdint>
#include <vector>

#include "bvh2.h"
#include "bvh4.h"

namespace pt {

/// The 4-wide tree before leaf blocks are filled in.
struct Bvh4Topology {
  std::vector<Bvh4Node> nodes;        ///< depth-first, root first (if the root is inner)
  std::vector<uint32_t> block_prims;  ///< 4 lanes per block in BVH order: input primitive or kInvalidId
  uint32_t root = bvh4_ref::kEmptyRef;
  uint32_t leaves = 0;
  int depth = 0;        ///< inner-node levels on the longest root-to-leaf path
  double sah_cost = 0;  ///< sum of area-weighted node visits + block tests, root area = 1
};

/// Collapses `bvh2`. Every child box is enlarged by `padding` on each side
/// (see SceneBvh4 for why). Leaves of more than 4 * kMaxLeafBlocks primitives
/// are not representable: build the binary BVH with max_leaf_size <= 64.
Bvh4Topology collapse_to_bvh4(const Bvh2& bvh2, float padding);

}  // namespace pt
