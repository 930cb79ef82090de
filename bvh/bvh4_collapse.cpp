// collapse_to_bvh4: a bottom-up dynamic program picks, for every binary node,
// the cheapest way (by SAH) to represent its subtree with 1..4 subtrees of a
// 4-wide parent: as a leaf, as one 4-wide node, or split between its two
// children (Ylitie, Karras and Laine 2017, without their 8-wide quantisation).
// A depth-first pass then emits nodes and leaf blocks.
#include "bvh4_collapse.h"

#include <algorithm>
#include <array>
#include <cassert>

#include "kernels/math/ray.h"

namespace pt {
namespace {

/// Per binary node: the SAH cost of representing its subtree with at most i
/// subtrees (cost[i - 1]) and how that optimum is reached.
struct Plan {
  std::array<float, 4> cost;
  std::array<int8_t, 4> left_slots;  ///< 0: as with one slot fewer; k > 0: k to the left child
  bool leaf = false;                 ///< one slot: a leaf (else a 4-wide node)
  int8_t node_split = 0;             ///< as a 4-wide node: slots of the left child (1..3)
  uint32_t first = 0, count = 0;     ///< primitive range prim_order[first, first + count)
};

class Collapser {
 public:
  Collapser(const Bvh2& bvh2, float padding, const CollapseCosts& costs, std::span<const uint32_t> prim_key)
      : in_(bvh2), pad_(padding), costs_(costs), key_(prim_key), plans_(bvh2.nodes.size()) {
    if (bvh2.nodes.empty()) return;
    BBox root = bvh2.nodes[0].bounds();
    float3 e = root.extent();
    volume_weight_ = costs.ray_length > 0.0f ? 2.0f / (costs.ray_length * (e.x + e.y + e.z) / 3.0f) : 0.0f;
    float w = weight(root);
    inv_root_area_ = w > 0.0f ? 1.0f / w : 0.0f;
  }

  Bvh4Topology run() {
    if (in_.prim_order.empty()) return std::move(out_);
    for (size_t i = in_.nodes.size(); i-- > 0;) plan(static_cast<uint32_t>(i));
    out_.root = emit_child(0, 1);
    return std::move(out_);
  }

 private:
  /// Chance that a ray visits box b, up to a factor: surface area plus the
  /// volume term of rays that start inside (see CollapseCosts::ray_length).
  float weight(const BBox& b) const {
    if (b.empty()) return 0.0f;
    float3 e = b.extent();
    return b.half_area() + volume_weight_ * e.x * e.y * e.z;
  }
  float area(uint32_t n) const { return weight(in_.nodes[n].bounds()) * inv_root_area_; }
  uint32_t blocks(uint32_t count) const { return (count + 3) / 4; }
  float leaf_cost(uint32_t count) const { return costs_.leaf + costs_.block * blocks(count); }

  /// Fills plans_[n]; children have larger indices, so they are planned first.
  void plan(uint32_t n) {
    const Bvh2Node& node = in_.nodes[n];
    Plan& p = plans_[n];
    if (node.is_leaf()) {
      p.first = node.left_or_first;
      p.count = node.count;
      p.leaf = true;
      p.cost.fill(area(n) * leaf_cost(node.count));
      p.left_slots.fill(0);
      return;
    }
    const Plan &l = plans_[node.left_or_first], &r = plans_[node.left_or_first + 1];
    assert(r.first == l.first + l.count);
    p.first = l.first;
    p.count = l.count + r.count;
    // Best split of j slots between the children, for j = 2..4.
    float split[5] = {INFINITY, INFINITY, INFINITY, INFINITY, INFINITY};
    int8_t split_left[5] = {};
    for (int j = 2; j <= 4; ++j)
      for (int k = 1; k < j; ++k)
        if (float c = l.cost[k - 1] + r.cost[j - k - 1]; c < split[j]) {
          split[j] = c;
          split_left[j] = int8_t(k);
        }
    float as_node = area(n) * costs_.node + split[4];
    float as_leaf = p.count <= costs_.max_leaf_size ? area(n) * leaf_cost(p.count) : INFINITY;
    p.leaf = as_leaf <= as_node;
    p.node_split = split_left[4];
    p.cost[0] = std::min(as_leaf, as_node);
    p.left_slots[0] = 0;
    for (int i = 2; i <= 4; ++i) {
      bool fewer = p.cost[i - 2] <= split[i];
      p.cost[i - 1] = fewer ? p.cost[i - 2] : split[i];
      p.left_slots[i - 1] = fewer ? 0 : split_left[i];
    }
  }

  /// The subtrees that fill `slots` slots for binary node n.
  void gather(uint32_t n, int slots, std::vector<uint32_t>& out) const {
    const Plan& p = plans_[n];
    if (slots == 1) {
      out.push_back(n);
      return;
    }
    int k = p.left_slots[slots - 1];
    if (k == 0) return gather(n, slots - 1, out);
    gather(in_.nodes[n].left_or_first, k, out);
    gather(in_.nodes[n].left_or_first + 1, slots - k, out);
  }

  /// Emits binary node n as one child (leaf or 4-wide node) at level `depth`.
  uint32_t emit_child(uint32_t n, int depth) {
    const Plan& p = plans_[n];
    if (p.leaf) return emit_leaf(n);
    out_.depth = std::max(out_.depth, depth);
    out_.sah_cost += area(n) * costs_.node;
    std::vector<uint32_t> kids;
    gather(in_.nodes[n].left_or_first, p.node_split, kids);
    gather(in_.nodes[n].left_or_first + 1, 4 - p.node_split, kids);
    uint32_t slot = static_cast<uint32_t>(out_.nodes.size());
    out_.nodes.emplace_back();
    for (int i = 0; i < 4; ++i) set_bounds(slot, i, i < int(kids.size()) ? in_.nodes[kids[i]].bounds() : BBox{});
    for (int i = 0; i < 4; ++i) {
      uint32_t ref = i < int(kids.size()) ? emit_child(kids[i], depth + 1) : bvh4_ref::kEmptyRef;
      out_.nodes[slot].child[i] = ref;  // `emit_child` may have grown nodes: index, never hold references
    }
    return bvh4_ref::inner(slot);
  }

  void set_bounds(uint32_t slot, int lane, const BBox& b) {
    Bvh4Node& node = out_.nodes[slot];
    bool empty = b.empty();
    for (int a = 0; a < 3; ++a) {
      node.bounds[2 * a][lane] = empty ? INFINITY : b.lower[a] - pad_;
      node.bounds[2 * a + 1][lane] = empty ? -INFINITY : b.upper[a] + pad_;
    }
  }

  uint32_t emit_leaf(uint32_t n) {
    const Plan& p = plans_[n];
    uint32_t first_block = static_cast<uint32_t>(out_.block_prims.size() / 4);
    size_t start = out_.block_prims.size();
    for (uint32_t i = 0; i < p.count; ++i) {
      uint32_t prim = in_.prim_order[p.first + i];
      bool repeated = false;
      if (!key_.empty())
        for (size_t k = start; k < out_.block_prims.size() && !repeated; ++k)
          repeated = key_[out_.block_prims[k]] == key_[prim];
      if (!repeated) out_.block_prims.push_back(prim);
    }
    uint32_t unique = static_cast<uint32_t>(out_.block_prims.size() - start);
    uint32_t count = blocks(unique);
    assert(count <= bvh4_ref::kMaxLeafBlocks);
    out_.block_prims.resize(start + 4 * size_t(count), kInvalidId);
    ++out_.leaves;
    out_.sah_cost += area(n) * leaf_cost(unique);
    return bvh4_ref::leaf(first_block, count);
  }

  const Bvh2& in_;
  float pad_;
  CollapseCosts costs_;
  std::span<const uint32_t> key_;
  float inv_root_area_ = 0.0f;
  float volume_weight_ = 0.0f;
  std::vector<Plan> plans_;
  Bvh4Topology out_;
};

}  // namespace

Bvh4Topology collapse_to_bvh4(const Bvh2& bvh2, float padding, const CollapseCosts& costs,
                              std::span<const uint32_t> prim_key) {
  return Collapser(bvh2, padding, costs, prim_key).run();
}

}  // namespace pt
