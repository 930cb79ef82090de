// The BVH4 overlays' queries: slots by depth, and the record of a walk.
#include "bvh4_inspect.h"

#include <algorithm>
#include <cmath>
#include <unordered_map>

#include "bvh4_query_table.h"

namespace pt {
namespace {

BBox slot_box(const Bvh4Node& n, int i) {
  return {{n.bounds[0][i], n.bounds[2][i], n.bounds[4][i]}, {n.bounds[1][i], n.bounds[3][i], n.bounds[5][i]}};
}

bool slot_used(const Bvh4Node& n, int i) { return n.child[i] != bvh4_ref::kEmptyRef; }

/// The union of the children of the root (or, for a root leaf, of its triangles).
BBox root_box(const Bvh4& bvh) {
  BBox b;
  if (bvh.empty()) return b;
  if (!bvh4_ref::is_leaf(bvh.root)) {
    const Bvh4Node& n = bvh.node(bvh.root);
    for (int i = 0; i < 4; ++i)
      if (slot_used(n, i)) b.expand(slot_box(n, i));
    return b;
  }
  const TriangleBlock4* blocks = bvh.leaf_blocks(bvh.root);
  for (uint32_t k = 0; k < bvh4_ref::leaf_block_count(bvh.root); ++k)
    for (int lane = 0; lane < 4; ++lane) {
      if (blocks[k].prim[lane] == kInvalidId) continue;
      float3 v0{blocks[k].v0[0][lane], blocks[k].v0[1][lane], blocks[k].v0[2][lane]};
      float3 r1{blocks[k].r1[0][lane], blocks[k].r1[1][lane], blocks[k].r1[2][lane]};
      float3 r2{blocks[k].r2[0][lane], blocks[k].r2[1][lane], blocks[k].r2[2][lane]};
      b.expand(v0);
      b.expand(v0 + r1);
      b.expand(v0 + r2);
    }
  return b;
}

void collect_level(const Bvh4& bvh, uint32_t ref, int depth, int target, size_t max_boxes, Bvh4Level& out) {
  if (bvh4_ref::is_leaf(ref)) return;
  const Bvh4Node& n = bvh.node(ref);
  for (int i = 0; i < 4 && !out.truncated; ++i) {  // once full, the rest of the tree is not walked
    if (!slot_used(n, i)) continue;
    if (depth + 1 == target) {
      if (out.boxes.size() < max_boxes) out.boxes.push_back(slot_box(n, i));
      else out.truncated = true;
    } else {
      collect_level(bvh, n.child[i], depth + 1, target, max_boxes, out);
    }
  }
}

int max_depth_below(const Bvh4& bvh, uint32_t ref, int depth) {
  if (bvh4_ref::is_leaf(ref)) return depth;
  const Bvh4Node& n = bvh.node(ref);
  int deepest = depth;
  for (int i = 0; i < 4; ++i)
    if (slot_used(n, i)) deepest = std::max(deepest, max_depth_below(bvh, n.child[i], depth + 1));
  return deepest;
}

/// Records a walk's visits: each node and leaf with its slot's box and
/// depth, known once its parent has been visited (the root: the union of its
/// children, depth 0).
class WalkRecord {
 public:
  WalkRecord(const Bvh4& bvh, size_t max_visits) : bvh_(bvh), max_visits_(max_visits) {
    slot_[bvh.root] = {root_box(bvh), 0};
  }
  static void visit(void* self, uint32_t ref) { static_cast<WalkRecord*>(self)->visit(ref); }
  Bvh4Walk& walk() { return walk_; }

 private:
  struct Slot {
    BBox box;
    uint32_t depth;
  };
  void visit(uint32_t ref) {
    const Slot slot = slot_.at(ref);
    const bool leaf = bvh4_ref::is_leaf(ref);
    if (walk_.visits.size() < max_visits_) walk_.visits.push_back({slot.box, slot.depth, leaf ? 1u : 0u});
    ++(leaf ? walk_.leaves : walk_.inner_nodes);
    if (leaf) return;
    const Bvh4Node& n = bvh_.node(ref);
    for (int i = 0; i < 4; ++i)
      if (slot_used(n, i)) slot_[n.child[i]] = {slot_box(n, i), slot.depth + 1};
  }

  const Bvh4& bvh_;
  size_t max_visits_;
  std::unordered_map<uint32_t, Slot> slot_;
  Bvh4Walk walk_;
};

}  // namespace

Bvh4Level bvh4_level(const Bvh4& bvh, int depth, size_t max_boxes) {
  Bvh4Level out;
  if (bvh.empty() || depth < 0) return out;
  if (depth == 0) {
    if (max_boxes > 0) out.boxes.push_back(root_box(bvh));
    else out.truncated = true;
    return out;
  }
  collect_level(bvh, bvh.root, 0, depth, max_boxes, out);
  return out;
}

int bvh4_max_depth(const Bvh4& bvh) { return bvh.empty() ? -1 : max_depth_below(bvh, bvh.root, 0); }

Bvh4Walk walk_bvh4(const SceneBvh4& bvh, const Ray& ray, size_t max_visits) {
  const bool traceable =
      is_finite(ray.org) && is_finite(ray.dir) && !std::isnan(ray.tmin) && !std::isnan(ray.tmax) && ray.tmin < ray.tmax;
  Hit hit{ray.tmax, 0.0f, 0.0f, kInvalidId};
  if (bvh.bvh().empty() || !traceable) {
    Bvh4Walk none;
    none.hit = hit;
    return none;
  }
  WalkRecord record(bvh.bvh(), max_visits);
  TraversalCounters counters;
  bvh4_query_table(bvh.isa()).walk_tree(bvh, ray, hit, counters, WalkRecord::visit, &record);
  record.walk().hit = hit;
  return std::move(record.walk());
}

}  // namespace pt
