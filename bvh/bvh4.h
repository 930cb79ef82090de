// The flattened 4-wide BVH: 128-byte nodes holding the six bound planes of
// four children as 4-float SoA, child references that say "node" or "leaf
// blocks" in their low bits, and leaves as blocks of four triangles stored in
// BVH order, already laid out for the 4-wide triangle tests (no index
// indirection while tracing).
#pragma once

#include <cstdint>
#include <vector>

#include "huge_page_allocator.h"
#include "kernels/simd/simd.h"

namespace pt {

/// 128 bytes, 64-byte aligned. bounds[2a] / bounds[2a + 1] are the lower /
/// upper planes of axis a for children 0..3. An empty slot has lower = +inf
/// and upper = -inf, so it fails the slab test without a branch; its child
/// reference is kEmptyRef and is never followed.
struct alignas(64) Bvh4Node {
  float bounds[6][4];  ///< 96 B: lower x, upper x, lower y, upper y, lower z, upper z
  uint32_t child[4];   ///< 16 B: child references (see bvh4_ref)
  uint32_t unused[4];  ///< 16 B: padding to two cache lines
};
static_assert(sizeof(Bvh4Node) == 128 && alignof(Bvh4Node) == 64);

/// 160 bytes, 32-byte aligned: four triangles as SoA rows (row[axis][lane]):
/// v0, e1 = v1 - v0, e2 = v2 - v0, the Moller-Trumbore test's. Vertex order
/// is the scene's, so barycentric u weights v1 and v weights v2. Padding
/// lanes are degenerate (never hit) and carry kInvalidId.
struct alignas(32) TriangleBlock4 {
  float v0[3][4];    ///< 48 B
  float r1[3][4];    ///< 48 B: e1 or v1
  float r2[3][4];    ///< 48 B: e2 or v2
  uint32_t prim[4];  ///< 16 B: triangle index in the input, or kInvalidId
};
static_assert(sizeof(TriangleBlock4) == 160 && alignof(TriangleBlock4) == 32);

/// Child references (uint32). An inner node is referenced by its byte offset
/// in the node array (a multiple of 128, bit 0 clear). A leaf by the byte
/// offset of its first block in the block array (a multiple of 32) with bit 0
/// set and bits 1..4 holding the block count minus one (1..16 blocks).
namespace bvh4_ref {
inline constexpr uint32_t kLeafBit = 1;
inline constexpr uint32_t kMaxLeafBlocks = 16;
inline constexpr uint32_t kEmptyRef = 0xFFFFFFFFu;

inline namespace PT_ISA_NS {
constexpr bool is_leaf(uint32_t ref) { return (ref & kLeafBit) != 0; }
constexpr uint32_t inner(uint32_t node_index) { return node_index * uint32_t(sizeof(Bvh4Node)); }
constexpr uint32_t node_index(uint32_t ref) { return ref / uint32_t(sizeof(Bvh4Node)); }
constexpr uint32_t leaf(uint32_t first_block, uint32_t block_count) {
  return first_block * uint32_t(sizeof(TriangleBlock4)) | (block_count - 1) << 1 | kLeafBit;
}
constexpr uint32_t leaf_offset(uint32_t ref) { return ref & ~31u; }
constexpr uint32_t leaf_block_count(uint32_t ref) { return ((ref >> 1) & 15u) + 1; }
}  // namespace PT_ISA_NS
}  // namespace bvh4_ref

/// The whole structure. `root` is an inner node or a leaf; with no triangles,
/// blocks is empty and nothing is ever hit.
struct Bvh4 {
  std::vector<Bvh4Node, HugePageAllocator<Bvh4Node>> nodes;
  std::vector<TriangleBlock4, HugePageAllocator<TriangleBlock4>> blocks;
  uint32_t root = bvh4_ref::kEmptyRef;

  bool empty() const { return blocks.empty(); }
  /// Bytes of nodes and leaf blocks.
  size_t bytes() const { return nodes.size() * sizeof(Bvh4Node) + blocks.size() * sizeof(TriangleBlock4); }
  const Bvh4Node& node(uint32_t ref) const {
    return *reinterpret_cast<const Bvh4Node*>(reinterpret_cast<const char*>(nodes.data()) + ref);
  }
  const TriangleBlock4* leaf_blocks(uint32_t ref) const {
    return reinterpret_cast<const TriangleBlock4*>(reinterpret_cast<const char*>(blocks.data()) +
                                                   bvh4_ref::leaf_offset(ref));
  }
};

}  // namespace pt
