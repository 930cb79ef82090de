// Binned SAH build of the binary BVH, parallel and deterministic. Every inner
// node of a range [begin, end) split at m is stored in slot m of a scratch
// array (split points are unique), so parallel subtrees never race for node
// indices and the tree does not depend on the thread count; a final
// depth-first pass packs the slots into Bvh2's adjacent-children layout.
#include <algorithm>
#include <bit>
#include <cmath>
#include <memory>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_invoke.h>
#include <oneapi/tbb/parallel_reduce.h>

#include "bvh2.h"
#include "kernels/simd/simd.h"

namespace pt {
namespace {

constexpr uint32_t kParallelTaskSize = 4096;     // subtrees at least this big become tasks
constexpr uint32_t kSweepMax = 16;               // ranges this small get the exact sweep
constexpr uint32_t kParallelBinSize = 1u << 16;  // ranges at least this big bin in parallel
constexpr uint32_t kBinGrain = 1u << 14;

/// 48 bytes: one primitive's box, centre and input index, moved by partitions.
struct alignas(16) PrimRef {
  float lower[4];  // x, y, z, unused
  float upper[4];
  float center[4];  // w = input index (bit pattern)
  uint32_t id() const { return std::bit_cast<uint32_t>(center[3]); }
};
static_assert(sizeof(PrimRef) == 48);

/// Box and centroid box of a set of primitives, as 4-float vectors.
/// Uninitialised when default-constructed; start from empty().
struct Bounds4 {
  vfloat4 lower, upper, clower, cupper;
  static Bounds4 empty() { return {vfloat4(INFINITY), vfloat4(-INFINITY), vfloat4(INFINITY), vfloat4(-INFINITY)}; }
  void add(const PrimRef& r) {
    vfloat4 c = vfloat4::load_aligned(r.center);
    lower = xsimd::min(lower, vfloat4::load_aligned(r.lower));
    upper = xsimd::max(upper, vfloat4::load_aligned(r.upper));
    clower = xsimd::min(clower, c);
    cupper = xsimd::max(cupper, c);
  }
  void add(const Bounds4& b) {
    lower = xsimd::min(lower, b.lower);
    upper = xsimd::max(upper, b.upper);
    clower = xsimd::min(clower, b.clower);
    cupper = xsimd::max(cupper, b.cupper);
  }
  /// Half surface area plus volume_weight times volume of the primitive box (0 when empty).
  float weight(float volume_weight) const {
    alignas(16) float e[4];
    xsimd::max(upper - lower, vfloat4(0.0f)).store_aligned(e);
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0] + volume_weight * e[0] * e[1] * e[2];
  }
  BBox box() const {
    alignas(16) float lo[4], hi[4];
    lower.store_aligned(lo);
    upper.store_aligned(hi);
    return {{lo[0], lo[1], lo[2]}, {hi[0], hi[1], hi[2]}};
  }
};

/// Maps centroids to bin indices along each axis of a centroid box.
struct BinMapping {
  vfloat4 origin, scale;
  uint32_t bins;
  BinMapping(const Bounds4& b, uint32_t bin_count) : origin(b.clower), bins(bin_count) {
    vfloat4 extent = b.cupper - b.clower;
    // Slightly under bins / extent so that the upper bound maps to bins - 1.
    scale = xsimd::select(extent > vfloat4(0.0f), vfloat4(bin_count * 0.99999f) / extent, vfloat4(0.0f));
  }
  vint4 bin_of(const PrimRef& r) const {
    vint4 k = xsimd::batch_cast<int32_t>((vfloat4::load_aligned(r.center) - origin) * scale);
    return xsimd::min(xsimd::max(k, vint4(0)), vint4(static_cast<int32_t>(bins) - 1));
  }
};

/// Per-axis bins of one range; only the first `bins` of each axis are used.
struct BinSet {
  Bounds4 bin[3][kMaxSahBins];
  uint32_t count[3][kMaxSahBins];

  void clear(uint32_t bins) {
    for (int a = 0; a < 3; ++a)
      for (uint32_t i = 0; i < bins; ++i) {
        bin[a][i] = Bounds4::empty();
        count[a][i] = 0;
      }
  }

  void add(const PrimRef& r, const BinMapping& m) {
    alignas(16) int32_t k[4];
    m.bin_of(r).store_aligned(k);
    for (int a = 0; a < 3; ++a) {
      bin[a][k[a]].add(r);
      ++count[a][k[a]];
    }
  }
  void add(const BinSet& o, uint32_t bins) {
    for (int a = 0; a < 3; ++a)
      for (uint32_t i = 0; i < bins; ++i) {
        bin[a][i].add(o.bin[a][i]);
        count[a][i] += o.count[a][i];
      }
  }
};

struct Range {
  uint32_t begin = 0, end = 0;
  Bounds4 bounds = Bounds4::empty();
  uint32_t size() const { return end - begin; }
};

struct Split {
  int axis = -1;
  uint32_t bin = 0;      ///< bins 0..bin go left
  bool ordered = false;  ///< the range is already partitioned: left_count first
  float cost = INFINITY;
  Bounds4 left = Bounds4::empty(), right = Bounds4::empty();
  uint32_t left_count = 0;
};

/// Scratch node: children are slots (count 0) or leaves [child, child + count).
struct SlotNode {
  BBox box[2];
  uint32_t child[2];
  uint32_t count[2];
};

class SahBuilder {
 public:
  SahBuilder(std::span<const BBox> boxes, std::span<const float3> centers, const SahBuildOptions& o);
  Bvh2 run();

 private:
  uint32_t blocks(uint32_t n) const { return (n + opt_.leaf_block - 1) / opt_.leaf_block; }
  /// Small ranges use fewer bins: clearing bins then costs more than binning.
  uint32_t bins_for(uint32_t n) const { return std::min(opt_.bins, std::max(n, 4u)); }
  void bin_range(const Range& r, const BinMapping& m, BinSet& set) const;
  Split best_split(const Range& r) const;
  Split sweep_split(const Range& r) const;
  uint32_t partition(const Range& r, const Split& s) const;
  Split median_split(const Range& r) const;
  /// Builds the subtree of `r` and returns its slot, or kLeaf when `r` is a leaf.
  uint32_t build(const Range& r, int depth);
  void child_of(SlotNode& n, int side, const Range& r, int depth);

  static constexpr uint32_t kLeaf = 0xFFFFFFFFu;
  SahBuildOptions opt_;
  float vw_ = 0.0f;  // weight of box volume against half area
  uint32_t size_;
  std::unique_ptr<PrimRef[]> refs_;    // uninitialised until filled
  std::unique_ptr<SlotNode[]> slots_;  // slot m: the inner node split at m
};

SahBuilder::SahBuilder(std::span<const BBox> boxes, std::span<const float3> centers, const SahBuildOptions& o)
    : opt_(o),
      size_(static_cast<uint32_t>(boxes.size())),
      refs_(new PrimRef[boxes.size()]),
      slots_(new SlotNode[boxes.size()]) {
  opt_.bins = std::clamp<uint32_t>(opt_.bins, 2, kMaxSahBins);
  opt_.leaf_block = std::max<uint32_t>(opt_.leaf_block, 1);
  opt_.max_leaf_size = std::max<uint32_t>(opt_.max_leaf_size, 1);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, boxes.size(), kBinGrain), [&](const tbb::blocked_range<size_t>& br) {
    for (size_t i = br.begin(); i != br.end(); ++i) {
      const BBox& b = boxes[i];
      const float3& c = centers[i];
      refs_[i] = {{b.lower.x, b.lower.y, b.lower.z, 0.0f},
                  {b.upper.x, b.upper.y, b.upper.z, 0.0f},
                  {c.x, c.y, c.z, std::bit_cast<float>(static_cast<uint32_t>(i))}};
    }
  });
}

void SahBuilder::bin_range(const Range& r, const BinMapping& m, BinSet& set) const {
  set.clear(m.bins);
  if (r.size() < kParallelBinSize) {
    for (uint32_t i = r.begin; i < r.end; ++i) set.add(refs_[i], m);
    return;
  }
  // Min, max and integer sums: the result does not depend on how TBB splits the range.
  auto empty = std::make_unique<BinSet>();
  empty->clear(m.bins);
  set = tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(r.begin, r.end, kBinGrain), *empty,
      [&](const tbb::blocked_range<uint32_t>& br, BinSet part) {
        for (uint32_t i = br.begin(); i != br.end(); ++i) part.add(refs_[i], m);
        return part;
      },
      [&](BinSet a, const BinSet& b) {
        a.add(b, m.bins);
        return a;
      });
}

Split SahBuilder::best_split(const Range& r) const {
  if (r.size() <= kSweepMax) return sweep_split(r);
  const uint32_t nb = bins_for(r.size());
  BinMapping m(r.bounds, nb);
  BinSet set;  // 13 KB, uninitialised but for the bins in use
  bin_range(r, m, set);
  Split best;
  for (int a = 0; a < 3; ++a) {
    float right_area[kMaxSahBins];
    uint32_t right_count[kMaxSahBins];
    Bounds4 acc = Bounds4::empty();
    uint32_t n = 0;
    for (uint32_t i = nb - 1; i > 0; --i) {
      acc.add(set.bin[a][i]);
      n += set.count[a][i];
      right_area[i] = acc.weight(vw_);
      right_count[i] = n;
    }
    Bounds4 left = Bounds4::empty();
    uint32_t nl = 0;
    for (uint32_t i = 0; i + 1 < nb; ++i) {
      left.add(set.bin[a][i]);
      nl += set.count[a][i];
      if (nl == 0 || right_count[i + 1] == 0) continue;
      float cost = left.weight(vw_) * blocks(nl) + right_area[i + 1] * blocks(right_count[i + 1]);
      if (cost < best.cost) {
        best.cost = cost;
        best.axis = a;
        best.bin = i;
        best.left = left;
        best.left_count = nl;
      }
    }
  }
  if (best.axis < 0) return best;
  for (uint32_t i = best.bin + 1; i < nb; ++i) best.right.add(set.bin[best.axis][i]);
  float parent_area = r.bounds.weight(vw_);
  best.cost = opt_.traversal_cost + (parent_area > 0.0f ? best.cost / parent_area : float(blocks(r.size())));
  return best;
}

uint32_t SahBuilder::partition(const Range& r, const Split& s) const {
  BinMapping m(r.bounds, bins_for(r.size()));
  PrimRef *first = refs_.get() + r.begin, *last = refs_.get() + r.end;
  auto mid = std::partition(first, last, [&](const PrimRef& p) {
    alignas(16) int32_t k[4];
    m.bin_of(p).store_aligned(k);
    return static_cast<uint32_t>(k[s.axis]) <= s.bin;
  });
  return static_cast<uint32_t>(mid - refs_.get());
}

/// Exact SAH over every object split of a small range along each axis; the
/// range is left sorted along the chosen axis.
Split SahBuilder::sweep_split(const Range& r) const {
  const uint32_t n = r.size();
  PrimRef* first = refs_.get() + r.begin;
  uint8_t order[3][kSweepMax];
  Split best;
  for (int a = 0; a < 3; ++a) {
    auto before = [&](uint8_t x, uint8_t y) {
      const PrimRef &p = first[x], &q = first[y];
      return p.center[a] < q.center[a] || (p.center[a] == q.center[a] && p.id() < q.id());
    };
    for (uint32_t i = 0; i < n; ++i) order[a][i] = uint8_t(i);
    std::sort(order[a], order[a] + n, before);
    float right_weight[kSweepMax];
    Bounds4 acc = Bounds4::empty();
    for (uint32_t i = n - 1; i > 0; --i) {
      acc.add(first[order[a][i]]);
      right_weight[i] = acc.weight(vw_);
    }
    Bounds4 left = Bounds4::empty();
    for (uint32_t i = 1; i < n; ++i) {
      left.add(first[order[a][i - 1]]);
      float cost = left.weight(vw_) * blocks(i) + right_weight[i] * blocks(n - i);
      if (cost < best.cost) {
        best.cost = cost;
        best.axis = a;
        best.left_count = i;
        best.left = left;
      }
    }
  }
  PrimRef sorted[kSweepMax];
  for (uint32_t i = 0; i < n; ++i) sorted[i] = first[order[best.axis][i]];
  for (uint32_t i = 0; i < n; ++i) first[i] = sorted[i];
  for (uint32_t i = best.left_count; i < n; ++i) best.right.add(first[i]);
  best.ordered = true;
  float parent_area = r.bounds.weight(vw_);
  best.cost = opt_.traversal_cost + (parent_area > 0.0f ? best.cost / parent_area : float(blocks(n)));
  return best;
}

/// Object median along the widest centroid axis (or by index if all centroids coincide).
Split SahBuilder::median_split(const Range& r) const {
  alignas(16) float lo[4], hi[4];
  r.bounds.clower.store_aligned(lo);
  r.bounds.cupper.store_aligned(hi);
  int axis = max_axis(float3{hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  PrimRef *first = refs_.get() + r.begin, *last = refs_.get() + r.end, *mid = first + r.size() / 2;
  std::nth_element(first, mid, last, [axis](const PrimRef& a, const PrimRef& b) {
    return a.center[axis] < b.center[axis] || (a.center[axis] == b.center[axis] && a.id() < b.id());
  });
  Split s;
  s.axis = axis;
  for (PrimRef* it = first; it != mid; ++it) s.left.add(*it);
  for (PrimRef* it = mid; it != last; ++it) s.right.add(*it);
  s.left_count = r.size() / 2;
  return s;
}

void SahBuilder::child_of(SlotNode& n, int side, const Range& r, int depth) {
  n.box[side] = r.bounds.box();
  uint32_t slot = build(r, depth);
  n.child[side] = slot == kLeaf ? r.begin : slot;
  n.count[side] = slot == kLeaf ? r.size() : 0;
}

uint32_t SahBuilder::build(const Range& r, int depth) {
  const uint32_t n = r.size();
  if (n <= 1) return kLeaf;
  // Near the depth limit, median splits keep the remaining depth at log2(n).
  bool near_limit = depth + std::bit_width(n) + 1 >= kBvh2MaxDepth;
  Split s = near_limit ? Split{} : best_split(r);
  if (!near_limit && n <= opt_.max_leaf_size && !(s.cost < float(blocks(n)))) return kLeaf;
  uint32_t mid = 0;
  if (s.ordered) {
    mid = r.begin + s.left_count;
  } else if (s.axis >= 0) {
    mid = partition(r, s);
  } else {
    s = median_split(r);
    mid = r.begin + s.left_count;
  }
  Range left{r.begin, mid, s.left}, right{mid, r.end, s.right};
  SlotNode& node = slots_[mid];
  if (n >= kParallelTaskSize)
    tbb::parallel_invoke([&] { child_of(node, 0, left, depth + 1); }, [&] { child_of(node, 1, right, depth + 1); });
  else {
    child_of(node, 0, left, depth + 1);
    child_of(node, 1, right, depth + 1);
  }
  return mid;
}

Bvh2 SahBuilder::run() {
  Bvh2 bvh;
  const uint32_t n = size_;
  Range root{0, n};
  root.bounds = tbb::parallel_reduce(
      tbb::blocked_range<uint32_t>(0, n, kBinGrain), Bounds4::empty(),
      [&](const tbb::blocked_range<uint32_t>& br, Bounds4 b) {
        for (uint32_t i = br.begin(); i != br.end(); ++i) b.add(refs_[i]);
        return b;
      },
      [](Bounds4 a, const Bounds4& b) {
        a.add(b);
        return a;
      });
  if (opt_.ray_length > 0.0f) {
    alignas(16) float e[4];
    (root.bounds.upper - root.bounds.lower).store_aligned(e);
    float mean_extent = (e[0] + e[1] + e[2]) / 3.0f;
    vw_ = mean_extent > 0.0f ? 2.0f / (opt_.ray_length * mean_extent) : 0.0f;
  }
  uint32_t root_slot = n == 0 ? kLeaf : build(root, 1);

  bvh.prim_order.resize(n);
  for (uint32_t i = 0; i < n; ++i) bvh.prim_order[i] = refs_[i].id();
  BBox box = root.bounds.box();
  bvh.nodes.push_back({box.lower, 0, box.upper, n});
  if (root_slot == kLeaf) return bvh;
  // Depth first: (Bvh2 node index, slot) pairs; children are appended in pairs.
  std::vector<std::pair<uint32_t, uint32_t>> stack{{0, root_slot}};
  while (!stack.empty()) {
    auto [index, slot] = stack.back();
    stack.pop_back();
    const SlotNode& s = slots_[slot];
    uint32_t first = static_cast<uint32_t>(bvh.nodes.size());
    bvh.nodes[index].left_or_first = first;
    bvh.nodes[index].count = 0;
    for (int side = 0; side < 2; ++side)
      bvh.nodes.push_back({s.box[side].lower, s.child[side], s.box[side].upper, s.count[side]});
    for (int side = 1; side >= 0; --side)
      if (s.count[side] == 0) stack.push_back({first + side, s.child[side]});
  }
  return bvh;
}

}  // namespace

Bvh2 build_bvh2_sah(std::span<const BBox> boxes, std::span<const float3> centers, const SahBuildOptions& options) {
  return SahBuilder(boxes, centers, options).run();
}

}  // namespace pt
