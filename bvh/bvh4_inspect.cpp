// The BVH4 overlays' queries: slots by depth, and a scalar closest-hit walk
// that records what it visits.
#include "bvh4_inspect.h"

#include <algorithm>
#include <cmath>

#include "triangle4_intersect.h"

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
      bool edges = bvh.form == TriangleForm::kMollerTrumbore;
      b.expand(v0);
      b.expand(edges ? v0 + r1 : r1);
      b.expand(edges ? v0 + r2 : r2);
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

/// The node test's per-ray constants and its slab test, one child at a time.
struct SlabRay {
  float rdir[3], org_rdir[3], tmin;
  bool fused;

  SlabRay(const Ray& r, bool fused_mul_sub) : tmin(r.tmin), fused(fused_mul_sub) {
    for (int a = 0; a < 3; ++a) {
      float d = r.dir[a];
      constexpr float kMinDir = 1e-18f;  // as NodeRay clamps
      float safe = std::fabs(d) < kMinDir ? std::copysign(kMinDir, d) : d;
      rdir[a] = 1.0f / safe;
      org_rdir[a] = r.org[a] * rdir[a];
    }
  }
  float plane(float p, int a) const { return fused ? std::fma(p, rdir[a], -org_rdir[a]) : p * rdir[a] - org_rdir[a]; }
  /// Whether the ray meets slot i within [tmin, tmax]; its entry distance in `tnear`.
  bool hits(const Bvh4Node& n, int i, float tmax, float& tnear) const {
    float tn = tmin, tf = tmax;
    for (int a = 0; a < 3; ++a) {
      float lo = plane(n.bounds[2 * a][i], a), hi = plane(n.bounds[2 * a + 1][i], a);
      bool positive = rdir[a] >= 0.0f;
      tn = std::max(tn, positive ? lo : hi);
      tf = std::min(tf, positive ? hi : lo);
    }
    tnear = tn;
    return tn <= tf;
  }
};

struct Pending {
  uint32_t ref;
  float dist;
  BBox box;
  uint32_t depth;
};

/// Orders two entries so that the nearer one ends up later (on top).
void order_far_first(Pending& a, Pending& b) {
  if (a.dist < b.dist) std::swap(a, b);
}

/// The children hit, in slot order: the one to descend into next, the others
/// pushed as the traversal pushes them (one: none; two: the farther, the
/// first slot winning a tie; three or four: sorted by the same networks).
Pending nearest_and_push_rest(Pending* hit, int count, std::vector<Pending>& stack) {
  if (count == 1) return hit[0];
  if (count == 2) {
    bool first_near = hit[0].dist <= hit[1].dist;
    stack.push_back(first_near ? hit[1] : hit[0]);
    return first_near ? hit[0] : hit[1];
  }
  if (count == 3) {
    order_far_first(hit[0], hit[1]);
    order_far_first(hit[1], hit[2]);
    order_far_first(hit[0], hit[1]);
  } else {
    order_far_first(hit[0], hit[1]);
    order_far_first(hit[2], hit[3]);
    order_far_first(hit[0], hit[2]);
    order_far_first(hit[1], hit[3]);
    order_far_first(hit[1], hit[2]);
  }
  for (int k = 0; k + 1 < count; ++k) stack.push_back(hit[k]);
  return hit[count - 1];
}

class Walker {
 public:
  Walker(const Bvh4& bvh, const Ray& ray, bool fused, size_t max_visits)
      : bvh_(bvh), ray_(ray), slab_(ray, fused), mt_(ray), max_visits_(max_visits) {}

  Bvh4Walk run() {
    walk_.hit = Hit{ray_.tmax, 0.0f, 0.0f, kInvalidId};
    tmax_ = ray_.tmax;
    std::vector<Pending> stack;
    Pending cur{bvh_.root, 0.0f, root_box(bvh_), 0};
    for (;;) {
      while (!bvh4_ref::is_leaf(cur.ref)) {
        record(cur, false);
        ++walk_.inner_nodes;
        const Bvh4Node& n = bvh_.node(cur.ref);
        Pending hit[4];
        int count = 0;
        for (int i = 0; i < 4; ++i) {
          float d = 0.0f;
          if (slot_used(n, i) && slab_.hits(n, i, tmax_, d))
            hit[count++] = {n.child[i], d, slot_box(n, i), cur.depth + 1};
        }
        if (count == 0) goto pop;
        cur = nearest_and_push_rest(hit, count, stack);
      }
      record(cur, true);
      ++walk_.leaves;
      test_leaf(cur.ref);
    pop:
      do {
        if (stack.empty()) return walk_;
        cur = stack.back();
        stack.pop_back();
      } while (cur.dist > tmax_);
    }
  }

 private:
  void record(const Pending& p, bool leaf) {
    if (walk_.visits.size() < max_visits_) walk_.visits.push_back({p.box, p.depth, leaf ? 1u : 0u});
  }
  void test_leaf(uint32_t ref) {
    const TriangleBlock4* blocks = bvh_.leaf_blocks(ref);
    for (uint32_t k = 0; k < bvh4_ref::leaf_block_count(ref); ++k) {
      BlockHits h;
      vfloat4 vtmax(tmax_);
      uint32_t mask = bvh_.form == TriangleForm::kMollerTrumbore
                          ? intersect_block_mt(blocks[k], mt_, vtmax, h)
                          : intersect_block_watertight(blocks[k], WatertightBlockRay(ray_), vtmax, h);
      if (mask == 0) continue;
      alignas(16) float t[4], u[4], v[4];
      h.t.store_aligned(t);
      h.u.store_aligned(u);
      h.v.store_aligned(v);
      int lane = 0;
      for (int i = 1; i < 4; ++i)
        if (t[i] < t[lane]) lane = i;
      tmax_ = t[lane];
      walk_.hit = {t[lane], u[lane], v[lane], blocks[k].prim[lane]};
    }
  }

  const Bvh4& bvh_;
  const Ray& ray_;
  SlabRay slab_;
  MtBlockRay mt_;
  size_t max_visits_;
  float tmax_ = 0.0f;
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

Bvh4Walk walk_bvh4(const Bvh4& bvh, const Ray& ray, bool fused, size_t max_visits) {
  const bool traceable =
      is_finite(ray.org) && is_finite(ray.dir) && !std::isnan(ray.tmin) && !std::isnan(ray.tmax) && ray.tmin < ray.tmax;
  if (bvh.empty() || !traceable) {
    Bvh4Walk none;
    none.hit = Hit{ray.tmax, 0.0f, 0.0f, kInvalidId};
    return none;
  }
  return Walker(bvh, ray, fused, max_visits).run();
}

}  // namespace pt
