// K consecutive items of an SoA stream as one register per field, generated
// from the stream's own field list (streams.h), so that a field added to a
// stream is loaded, stored and compacted wherever its lanes move: lane
// structs, aligned loads and stores at lane boundaries, and appends of the
// lanes in a mask (compaction by store_compressed, kernels/simd/simd.h). For code
// compiled per instruction-set level.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/simd.h"
#include "streams.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// The K-wide register of a stream field's type.
template <class T>
struct LaneOf;
template <>
struct LaneOf<float> {
  using type = vfloatK;
};
template <>
struct LaneOf<uint32_t> {
  using type = vuintK;
};
template <class T>
using lane_t = typename LaneOf<T>::type;

/// Makes room for K more items, the most one compressed append can write.
template <class Stream>
inline void reserve_lanes(Stream& s) {
  if (s.size + kLanes > s.capacity) s.reserve(2 * s.capacity + kLanes);
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf

#define PT_SOA_LANE_MEMBER(T, name) ::pt::wf::lane_t<T> name;
#define PT_SOA_LANE_LOAD(T, name) l.name = ::pt::wf::lane_t<T>::load_aligned(&s.name[i]);
#define PT_SOA_LANE_STORE(T, name) l.name.store_aligned(&s.name[i]);
#define PT_SOA_LANE_APPEND(T, name) ::pt::store_compressed(&s.name[at], mask, l.name);

/// Declares LANES, one register per field of FIELDS (in order, for designated
/// initialisers), and for STREAM: load_lanes(s, i) and store_lanes(s, i, l)
/// of items [i, i + K) (i a multiple of K), and append_lanes(s, mask, l),
/// which appends the lanes set in `mask`, in lane order.
#define PT_SOA_LANES(LANES, STREAM, FIELDS)                                                  \
  struct LANES {                                                                             \
    FIELDS(PT_SOA_LANE_MEMBER)                                                               \
  };                                                                                         \
  inline LANES load_lanes(const STREAM& s, size_t i) {                                       \
    LANES l;                                                                                 \
    FIELDS(PT_SOA_LANE_LOAD)                                                                 \
    return l;                                                                                \
  }                                                                                          \
  inline void store_lanes(STREAM& s, size_t i, const LANES& l) { FIELDS(PT_SOA_LANE_STORE) } \
  inline void append_lanes(STREAM& s, uint32_t mask, const LANES& l) {                       \
    if (!mask) return;                                                                       \
    ::pt::wf::reserve_lanes(s);                                                              \
    size_t at = s.size;                                                                      \
    FIELDS(PT_SOA_LANE_APPEND)                                                               \
    s.size += static_cast<size_t>(std::popcount(mask));                                      \
  }

namespace pt::wf {
inline namespace PT_ISA_NS {

PT_SOA_LANES(PathLanes, PathState, PT_PATH_FIELDS)
PT_SOA_LANES(RayLanes, RayQueue, PT_RAY_FIELDS)
PT_SOA_LANES(HitLanes, HitQueue, PT_HIT_FIELDS)
PT_SOA_LANES(ShadowLanes, ShadowQueue, PT_SHADOW_FIELDS)

}  // namespace PT_ISA_NS
}  // namespace pt::wf
