// collapse_to_bvh4: depth-first emission of nodes and leaf blocks.
#include "bvh4_collapse.h"

#include <algorithm>
#include <cassert>

#include "kernels/ray.h"

namespace pt {
namespace {

class Collapser {
 public:
  Collapser(const Bvh2& bvh2, float padding) : in_(bvh2), pad_(padding) {
    float root_area = bvh2.nodes.empty() ? 0.0f : bvh2.nodes[0].bounds().half_area();
    inv_root_area_ = root_area > 0.0f ? 1.0 / root_area : 0.0;
  }

  Bvh4Topology run() {
    if (!in_.prim_order.empty()) out_.root = emit(0, 1);
    return std::move(out_);
  }

 private:
  /// Emits the subtree of binary node `index` at 4-wide level `depth`; returns its reference.
  uint32_t emit(uint32_t index, int depth) {
    const Bvh2Node& n = in_.nodes[index];
    if (n.is_leaf()) return emit_leaf(n);
    out_.depth = std::max(out_.depth, depth);
    out_.sah_cost += n.bounds().half_area() * inv_root_area_;
    uint32_t kids[4];
    int count = gather_children(n, kids);
    uint32_t slot = static_cast<uint32_t>(out_.nodes.size());
    out_.nodes.emplace_back();
    for (int i = 0; i < 4; ++i) set_bounds(slot, i, i < count ? in_.nodes[kids[i]].bounds() : BBox{});
    for (int i = 0; i < 4; ++i) {
      uint32_t ref = i < count ? emit(kids[i], depth + 1) : bvh4_ref::kEmptyRef;
      out_.nodes[slot].child[i] = ref;  // `emit` may have grown nodes: index, never hold references
    }
    return bvh4_ref::inner(slot);
  }

  /// The binary children of `n`, with the largest-area inner child opened until there are four.
  int gather_children(const Bvh2Node& n, uint32_t kids[4]) const {
    int count = 2;
    kids[0] = n.left_or_first;
    kids[1] = n.left_or_first + 1;
    while (count < 4) {
      int best = -1;
      float best_area = -1.0f;
      for (int i = 0; i < count; ++i) {
        const Bvh2Node& c = in_.nodes[kids[i]];
        if (!c.is_leaf() && c.bounds().half_area() > best_area) { best = i; best_area = c.bounds().half_area(); }
      }
      if (best < 0) break;
      uint32_t first = in_.nodes[kids[best]].left_or_first;
      kids[best] = first;  // keep left-to-right order: the left grandchild takes the slot
      std::copy_backward(kids + best + 1, kids + count, kids + count + 1);
      kids[best + 1] = first + 1;
      ++count;
    }
    return count;
  }

  void set_bounds(uint32_t slot, int lane, const BBox& b) {
    Bvh4Node& node = out_.nodes[slot];
    bool empty = b.empty();
    for (int a = 0; a < 3; ++a) {
      node.bounds[2 * a][lane] = empty ? INFINITY : b.lower[a] - pad_;
      node.bounds[2 * a + 1][lane] = empty ? -INFINITY : b.upper[a] + pad_;
    }
  }

  uint32_t emit_leaf(const Bvh2Node& n) {
    uint32_t blocks = (n.count + 3) / 4;
    assert(blocks <= bvh4_ref::kMaxLeafBlocks);
    uint32_t first_block = static_cast<uint32_t>(out_.block_prims.size() / 4);
    for (uint32_t i = 0; i < blocks * 4; ++i)
      out_.block_prims.push_back(i < n.count ? in_.prim_order[n.left_or_first + i] : kInvalidId);
    ++out_.leaves;
    out_.sah_cost += n.bounds().half_area() * inv_root_area_ * blocks;
    return bvh4_ref::leaf(first_block, blocks);
  }

  const Bvh2& in_;
  float pad_;
  double inv_root_area_ = 0.0;
  Bvh4Topology out_;
};

}  // namespace

Bvh4Topology collapse_to_bvh4(const Bvh2& bvh2, float padding) { return Collapser(bvh2, padding).run(); }

}  // namespace pt
