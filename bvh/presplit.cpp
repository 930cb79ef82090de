// presplit_triangles: priorities, the split budget's scale, and the recursive
// cutting of each chosen triangle at grid planes, clipping the triangle to
// each fragment's cell in double precision with a margin for rounding.
#include "presplit.h"

#include <algorithm>
#include <cmath>

#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_reduce.h>

namespace pt {
namespace {

constexpr uint32_t kMaxSplitsPerTriangle = 64;
constexpr int kMaxGridLevel = 24;
constexpr size_t kGrain = 4096;

struct DBox {
  double lo[3], hi[3];
  double half_area() const {
    double e[3];
    for (int a = 0; a < 3; ++a) e[a] = std::max(hi[a] - lo[a], 0.0);
    return e[0] * e[1] + e[1] * e[2] + e[2] * e[0];
  }
  double volume() const {
    double v = 1.0;
    for (int a = 0; a < 3; ++a) v *= std::max(hi[a] - lo[a], 0.0);
    return v;
  }
};

struct Point {
  double p[3];
};

/// The scene's power-of-two grid: planes lo + k extent / 2^level.
struct Grid {
  double lo[3], extent[3];

  /// The coarsest plane strictly inside (lo, hi) along `axis`, or level 0 when none is.
  int coarsest_plane(int axis, double lo, double hi, double& pos) const {
    if (!(extent[axis] > 0.0)) return 0;
    for (int level = 1; level <= kMaxGridLevel; ++level) {
      double cell = std::ldexp(extent[axis], -level);
      double x = this->lo[axis] + (std::floor((lo - this->lo[axis]) / cell) + 1.0) * cell;
      if (x > lo && x < hi) {
        pos = x;
        return level;
      }
    }
    return 0;
  }

  /// The plane to cut `b` at: the coarsest over all axes, the widest axis on ties.
  int choose_plane(const DBox& b, int& axis, double& pos) const {
    int best = 0;
    for (int a = 0; a < 3; ++a) {
      double x;
      int level = coarsest_plane(a, b.lo[a], b.hi[a], x);
      if (level == 0) continue;
      bool better = best == 0 || level < best || (level == best && b.hi[a] - b.lo[a] > b.hi[axis] - b.lo[axis]);
      if (better) {
        best = level;
        axis = a;
        pos = x;
      }
    }
    return best;
  }
};

/// Clips the triangle to box `b` (Sutherland-Hodgman, six planes, in double)
/// and returns the clipped polygon's box, widened by 2^-40 of the box's
/// magnitude (far above the rounding of the intersection points) and kept
/// inside `b`; false when nothing is left. Should rounding ever produce more
/// vertices than a convex clip can, the box is `b` itself (still conservative).
bool clipped_box(const Point (&tri)[3], const DBox& b, DBox& out) {
  constexpr int kMaxVertices = 32;
  Point poly[kMaxVertices], next[kMaxVertices];
  int n = 3;
  for (int i = 0; i < 3; ++i) poly[i] = tri[i];
  for (int a = 0; a < 3 && n > 0; ++a)
    for (int side = 0; side < 2 && n > 0; ++side) {
      double plane = side == 0 ? b.lo[a] : b.hi[a];
      auto inside = [&](const Point& q) { return side == 0 ? q.p[a] >= plane : q.p[a] <= plane; };
      int m = 0;
      for (int i = 0; i < n; ++i) {
        const Point &cur = poly[i], &nxt = poly[(i + 1) % n];
        bool in_cur = inside(cur), in_nxt = inside(nxt);
        if (m + 2 > kMaxVertices) {
          out = b;
          return true;
        }
        if (in_cur) next[m++] = cur;
        if (in_cur != in_nxt) {
          double s = (plane - cur.p[a]) / (nxt.p[a] - cur.p[a]);
          Point x;
          for (int k = 0; k < 3; ++k) x.p[k] = cur.p[k] + s * (nxt.p[k] - cur.p[k]);
          x.p[a] = plane;
          next[m++] = x;
        }
      }
      n = m;
      for (int i = 0; i < n; ++i) poly[i] = next[i];
    }
  if (n == 0) return false;
  for (int a = 0; a < 3; ++a) {
    out.lo[a] = out.hi[a] = poly[0].p[a];
    for (int i = 1; i < n; ++i) {
      out.lo[a] = std::min(out.lo[a], poly[i].p[a]);
      out.hi[a] = std::max(out.hi[a], poly[i].p[a]);
    }
    double margin = std::max(std::fabs(b.lo[a]), std::fabs(b.hi[a])) * 0x1p-40;
    out.lo[a] = std::max(out.lo[a] - margin, b.lo[a]);
    out.hi[a] = std::min(out.hi[a] + margin, b.hi[a]);
  }
  return true;
}

/// A fragment's float box: the double box rounded outwards, never past the
/// triangle's own (exact) float box.
BBox rounded_out(const DBox& d, const BBox& tri) {
  BBox b;
  for (int a = 0; a < 3; ++a) {
    float lo = static_cast<float>(d.lo[a]), hi = static_cast<float>(d.hi[a]);
    if (double(lo) > d.lo[a]) lo = std::nextafter(lo, -INFINITY);
    if (double(hi) < d.hi[a]) hi = std::nextafter(hi, INFINITY);
    b.lower[a] = std::max(lo, tri.lower[a]);
    b.upper[a] = std::min(hi, tri.upper[a]);
  }
  return b;
}

DBox to_double(const BBox& b) { return {{b.lower.x, b.lower.y, b.lower.z}, {b.upper.x, b.upper.y, b.upper.z}}; }

/// Emits the fragments of one triangle: `splits` cuts below box `frag`.
void cut(const Grid& grid, const Point (&tri)[3], const BBox& tri_box, const DBox& frag, uint32_t splits, BBox* out,
         uint32_t& count) {
  int axis = 0;
  double pos = 0.0;
  DBox left = frag, right = frag, lbox, rbox;
  if (splits > 0 && grid.choose_plane(frag, axis, pos) != 0) {
    left.hi[axis] = pos;
    right.lo[axis] = pos;
    if (clipped_box(tri, left, lbox) && clipped_box(tri, right, rbox)) {
      double wl = lbox.half_area(), wr = rbox.half_area();
      uint32_t rest = splits - 1;
      uint32_t to_left = wl + wr > 0.0 ? static_cast<uint32_t>(std::lround(rest * wl / (wl + wr))) : rest / 2;
      to_left = std::min(to_left, rest);
      cut(grid, tri, tri_box, lbox, to_left, out, count);
      cut(grid, tri, tri_box, rbox, rest - to_left, out, count);
      return;
    }
  }
  out[count++] = rounded_out(frag, tri_box);
}

}  // namespace

SplitReferences presplit_triangles(std::span<const float3> corners, float budget) {
  const size_t n = corners.size() / 3;
  SplitReferences refs;
  std::vector<BBox> tri_box(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kGrain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      tri_box[i] = BBox::of_point(corners[3 * i]);
      tri_box[i].expand(corners[3 * i + 1]);
      tri_box[i].expand(corners[3 * i + 2]);
    }
  });
  if (!(budget > 0.0f) || n == 0) {
    refs.boxes = std::move(tri_box);
    refs.centers.resize(n);
    refs.triangle.resize(n);
    for (size_t i = 0; i < n; ++i) {
      refs.centers[i] = refs.boxes[i].center();
      refs.triangle[i] = static_cast<uint32_t>(i);
    }
    return refs;
  }

  BBox scene = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, kGrain), BBox{},
      [&](const tbb::blocked_range<size_t>& r, BBox b) {
        for (size_t i = r.begin(); i != r.end(); ++i) b.expand(tri_box[i]);
        return b;
      },
      [](BBox a, const BBox& b) { return merge(a, b); });
  Grid grid{};
  for (int a = 0; a < 3; ++a) {
    grid.lo[a] = scene.lower[a];
    grid.extent[a] = double(scene.upper[a]) - scene.lower[a];
  }

  // Priority: the volume of the triangle's box (the waste that rays starting
  // inside the scene pay for; a flat axis-aligned wall has none, and splitting
  // walls was measured to cost bounce and shadow rays more than it saved),
  // weighted by the coarseness of the first plane, to the power 1/3 (Karras
  // and Aila's X = 2, Y = 1/3, with volume in place of their area excess).
  std::vector<float> priority(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kGrain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      DBox box = to_double(tri_box[i]);
      int axis = 0;
      double pos = 0.0;
      int level = grid.choose_plane(box, axis, pos);
      double volume = box.volume();
      priority[i] = level == 0 || !(volume > 0.0) ? 0.0f : static_cast<float>(std::cbrt(std::ldexp(volume, -level)));
    }
  });

  // The scale D of splits = floor(D priority), at most kMaxSplitsPerTriangle
  // (clamped in double before conversion), that spends the budget, by
  // bisection; D = +inf when the budget is at least what can be spent.
  auto splits_of = [&](double scale, size_t i) -> uint32_t {
    return priority[i] > 0.0f ? static_cast<uint32_t>(std::min<double>(kMaxSplitsPerTriangle, scale * priority[i])) : 0;
  };
  auto splits_at = [&](double scale) {
    return tbb::parallel_reduce(
        tbb::blocked_range<size_t>(0, n, kGrain), uint64_t(0),
        [&](const tbb::blocked_range<size_t>& r, uint64_t sum) {
          for (size_t i = r.begin(); i != r.end(); ++i) sum += splits_of(scale, i);
          return sum;
        },
        [](uint64_t a, uint64_t b) { return a + b; });
  };
  const uint64_t target = static_cast<uint64_t>(double(budget) * double(n));
  double scale = 0.0;
  if (splits_at(INFINITY) <= target) {
    scale = INFINITY;
  } else {
    double max_priority = *std::max_element(priority.begin(), priority.end());
    double lo = 0.0, hi = kMaxSplitsPerTriangle / max_priority;  // max_priority > 0 here
    while (splits_at(hi) <= target) hi *= 2.0;                   // ends: at +inf the sum exceeds the target
    for (int it = 0; it < 40; ++it) {
      double mid = 0.5 * (lo + hi);
      (splits_at(mid) <= target ? lo : hi) = mid;
    }
    scale = lo;
  }

  // Fragments per triangle into fixed slots, then packed in triangle order.
  std::vector<size_t> first(n + 1, 0);
  for (size_t i = 0; i < n; ++i) first[i + 1] = first[i] + 1 + splits_of(scale, i);
  std::vector<BBox> slots(first[n]);
  std::vector<uint32_t> made(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, kGrain), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      uint32_t splits = static_cast<uint32_t>(first[i + 1] - first[i] - 1), count = 0;
      Point tri[3];  // with no splits, cut emits the triangle's own box (exact through double)
      for (int v = 0; v < 3; ++v)
        for (int k = 0; k < 3; ++k) tri[v].p[k] = corners[3 * i + v][k];
      cut(grid, tri, tri_box[i], to_double(tri_box[i]), splits, &slots[first[i]], count);
      made[i] = count;
    }
  });
  size_t total = 0;
  for (size_t i = 0; i < n; ++i) total += made[i];
  refs.boxes.reserve(total);
  refs.centers.reserve(total);
  refs.triangle.reserve(total);
  for (size_t i = 0; i < n; ++i)
    for (uint32_t k = 0; k < made[i]; ++k) {
      const BBox& b = slots[first[i] + k];
      refs.boxes.push_back(b);
      refs.centers.push_back(b.center());
      refs.triangle.push_back(static_cast<uint32_t>(i));
    }
  return refs;
}

}  // namespace pt
