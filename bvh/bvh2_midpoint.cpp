// Midpoint-split binary BVH build (the CS184 assignment's construct_bvh).
#include <algorithm>
#include <numeric>

#include "bvh2.h"

namespace pt {
namespace {

struct Task {
  uint32_t node, begin, end;
  int depth;
};

}  // namespace

Bvh2 build_bvh2_midpoint(std::span<const BBox> boxes, std::span<const float3> centers, uint32_t max_leaf_size) {
  Bvh2 bvh;
  uint32_t n = static_cast<uint32_t>(boxes.size());
  max_leaf_size = std::max<uint32_t>(max_leaf_size, 1);
  bvh.prim_order.resize(n);
  std::iota(bvh.prim_order.begin(), bvh.prim_order.end(), 0u);
  bvh.nodes.reserve(n == 0 ? 1 : 2 * n);
  bvh.nodes.emplace_back();
  if (n == 0) {
    bvh.nodes[0].lower = BBox{}.lower;
    bvh.nodes[0].upper = BBox{}.upper;
    return bvh;
  }
  std::vector<Task> stack{{0, 0, n, 1}};
  while (!stack.empty()) {
    Task t = stack.back();
    stack.pop_back();
    BBox box, centroid_box;
    for (uint32_t i = t.begin; i < t.end; ++i) {
      box.expand(boxes[bvh.prim_order[i]]);
      centroid_box.expand(centers[bvh.prim_order[i]]);
    }
    Bvh2Node& node = bvh.nodes[t.node];
    node.lower = box.lower;
    node.upper = box.upper;
    uint32_t count = t.end - t.begin;
    if (count <= max_leaf_size) {
      node.left_or_first = t.begin;
      node.count = count;
      continue;
    }
    int axis = max_axis(centroid_box.extent());
    float split = centroid_box.center()[axis];
    auto first = bvh.prim_order.begin() + t.begin, last = bvh.prim_order.begin() + t.end;
    auto mid = std::partition(first, last, [&](uint32_t p) { return centers[p][axis] < split; });
    if (mid == first || mid == last || t.depth >= kBvh2MaxDepth - 8) {
      mid = first + count / 2;  // degenerate split (or too deep): median
      std::nth_element(first, mid, last, [&](uint32_t a, uint32_t b) { return centers[a][axis] < centers[b][axis]; });
    }
    uint32_t left = static_cast<uint32_t>(bvh.nodes.size());
    node.left_or_first = left;
    node.count = 0;
    bvh.nodes.emplace_back();
    bvh.nodes.emplace_back();
    uint32_t m = static_cast<uint32_t>(mid - bvh.prim_order.begin());
    stack.push_back({left + 1, m, t.end, t.depth + 1});
    stack.push_back({left, t.begin, m, t.depth + 1});
  }
  bvh.nodes.shrink_to_fit();  // 2n were reserved; about n / 2 are used with leaves of 4
  return bvh;
}

Bvh2Shape bvh2_shape(const Bvh2& bvh) {
  Bvh2Shape s;
  if (bvh.nodes.empty()) return s;
  std::vector<std::pair<uint32_t, int>> stack{{0, 1}};
  while (!stack.empty()) {
    auto [i, d] = stack.back();
    stack.pop_back();
    s.depth = std::max(s.depth, d);
    const Bvh2Node& n = bvh.nodes[i];
    if (n.is_leaf() || n.left_or_first == 0) {
      s.leaves += n.is_leaf() ? 1 : 0;
      continue;
    }
    stack.push_back({n.left_or_first, d + 1});
    stack.push_back({n.left_or_first + 1, d + 1});
  }
  return s;
}

}  // namespace pt
