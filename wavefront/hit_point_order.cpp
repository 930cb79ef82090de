// sort_by_hit_point: cell keys K lanes at a time, a histogram, bucket
// starts, a stable scatter of indices, then every field of both queues
// gathered in the new order (K lanes per gather; a field of one value, as a
// bounce queue's tmin and tmax, filled instead).
#include "kernels/simd/isa_namespace.h"
#include "hit_point_order.h"

#include <utility>

#include "kernels/simd/simd.h"

namespace pt::wf {
inline namespace PT_ISA_NS {
namespace {

/// Bits 0..2 of each lane moved to bits 0, 3, 6 (one axis of a 9-bit Morton code).
inline vuintK spread3(vuintK x) { return (x & vuintK(1u)) | ((x & vuintK(2u)) << 2) | ((x & vuintK(4u)) << 4); }

/// The cell along one axis, [0, 8): outside the bounds (and NaN) clamped in.
inline vuintK axis_cell(vfloatK x, float lo, float scale) {
  vfloatK c = (x - vfloatK(lo)) * vfloatK(scale);
  c = xsimd::select(c > vfloatK(0.0f), xsimd::min(c, vfloatK(7.0f)), vfloatK(0.0f));
  return xsimd::batch_cast<uint32_t>(xsimd::batch_cast<int32_t>(c));
}

/// Whether items [0, n) of a field all hold item 0's bits (a bounce queue's
/// tmin and tmax); most fields differ within their first batch.
template <class T>
bool holds_one_value(const T* field, size_t n) {
  const uint32_t* bits = reinterpret_cast<const uint32_t*>(field);
  const vuintK first(bits[0]);
  const size_t whole = n / kLanes * kLanes;
  for (size_t j = 0; j < whole; j += kLanes)
    if (lane_mask(as_float_mask(vuintK::load_aligned(bits + j) != first)) != 0) return false;
  for (size_t j = whole; j < n; ++j)
    if (bits[j] != bits[0]) return false;
  return true;
}

/// to[j] = from[order[j]] for j in [0, n rounded up to K); order is padded.
/// A field of one value is copied as that value instead of gathered.
template <class T>
void gather_field(const T* from, T* to, const uint32_t* order, size_t n) {
  if (holds_one_value(from, n)) {
    std::fill(to, to + round_up_to_lanes(n), from[0]);
    return;
  }
  for (size_t j = 0; j < n; j += kLanes)
    gather(from, xsimd::bitwise_cast<vintK>(vuintK::load_aligned(order + j))).store_aligned(to + j);
}

#define PT_GATHER_FIELD(T, name) gather_field(from.name.data(), to.name.data(), order, n);

}  // namespace

void sort_by_hit_point(const BBox& b, RayQueue& rays, HitQueue& hits, HitPointOrder& s) {
  constexpr uint32_t kMiss = HitPointOrder::kCells;
  const size_t n = rays.size;
  if (n < 2) return;
  auto scale_of = [](float e) { return e > 0.0f && e < kInfinity ? 8.0f / e : 0.0f; };
  const float sx = scale_of(b.upper.x - b.lower.x), sy = scale_of(b.upper.y - b.lower.y),
              sz = scale_of(b.upper.z - b.lower.z);

  const size_t padded = round_up_to_lanes(n);
  if (s.cell.size() < padded) s.cell.resize(padded);
  if (s.order.size() < padded) s.order.resize(padded);
  uint32_t* __restrict cell = s.cell.data();
  const float *ox = rays.org_x.data(), *oy = rays.org_y.data(), *oz = rays.org_z.data();
  const float *dx = rays.dir_x.data(), *dy = rays.dir_y.data(), *dz = rays.dir_z.data();
  const float* t = hits.t.data();
  const uint32_t* prim = hits.prim.data();
  for (size_t i = 0; i < n; i += kLanes) {  // the arrays are padded to whole batches
    const vfloatK ti = vfloatK::load_aligned(t + i);
    const vuintK key =
        spread3(axis_cell(vfloatK::load_aligned(ox + i) + ti * vfloatK::load_aligned(dx + i), b.lower.x, sx)) |
        spread3(axis_cell(vfloatK::load_aligned(oy + i) + ti * vfloatK::load_aligned(dy + i), b.lower.y, sy)) << 1 |
        spread3(axis_cell(vfloatK::load_aligned(oz + i) + ti * vfloatK::load_aligned(dz + i), b.lower.z, sz)) << 2;
    const auto miss = vuintK::load_aligned(prim + i) == vuintK(kInvalidId);
    xsimd::select(miss, vuintK(kMiss), key).store_aligned(cell + i);
  }
  uint32_t start[kMiss + 2] = {};  // start[c + 1] counts cell c, then start[c] = cell c's first slot
  for (size_t i = 0; i < n; ++i) ++start[cell[i] + 1];
  for (uint32_t c = 0; c <= kMiss; ++c) start[c + 1] += start[c];
  uint32_t* __restrict order = s.order.data();
  for (size_t i = 0; i < n; ++i) order[start[cell[i]]++] = static_cast<uint32_t>(i);
  for (size_t i = n; i < padded; ++i) order[i] = 0;  // the last batch's spare lanes read item 0

  s.rays.reserve(n);
  s.hits.reserve(n);
  s.rays.size = s.hits.size = n;
  {
    const RayQueue& from = rays;
    RayQueue& to = s.rays;
    PT_RAY_FIELDS(PT_GATHER_FIELD)
  }
  {
    const HitQueue& from = hits;
    HitQueue& to = s.hits;
    PT_HIT_FIELDS(PT_GATHER_FIELD)
  }
  std::swap(rays, s.rays);
  std::swap(hits, s.hits);
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
