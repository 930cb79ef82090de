// A wavefront stream's items as plain columns, one vector of 32-bit words per
// field in the stream's field order (wavefront/streams.h): the form in which
// tests, compiled once, hand streams to the probes of a level (lane_probes.h),
// whose stream types are the level's own (kernels/simd/isa_namespace.h).
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include "kernels/simd/isa_namespace.h"
#include "wavefront/streams.h"

namespace pt::test {

using StreamColumns = std::vector<std::vector<uint32_t>>;

inline namespace PT_ISA_NS {

#define PT_TO_COLUMN(T, name)    \
  static_assert(sizeof(T) == 4); \
  columns.emplace_back(s.size);  \
  if (s.size) std::memcpy(columns.back().data(), s.name.data(), 4 * s.size);
#define PT_FROM_COLUMN(T, name)                                          \
  if (s.size) std::memcpy(s.name.data(), columns[f].data(), 4 * s.size); \
  ++f;
#define PT_STREAM_COLUMNS(Stream, FIELDS)                             \
  inline StreamColumns columns_of(const Stream& s) {                  \
    StreamColumns columns;                                            \
    FIELDS(PT_TO_COLUMN)                                              \
    return columns;                                                   \
  }                                                                   \
  inline void from_columns(const StreamColumns& columns, Stream& s) { \
    s.clear();                                                        \
    s.reserve(columns[0].size());                                     \
    s.size = columns[0].size();                                       \
    size_t f = 0;                                                     \
    FIELDS(PT_FROM_COLUMN)                                            \
  }

PT_STREAM_COLUMNS(wf::RayQueue, PT_RAY_FIELDS)
PT_STREAM_COLUMNS(wf::ShadowQueue, PT_SHADOW_FIELDS)
PT_STREAM_COLUMNS(wf::HitQueue, PT_HIT_FIELDS)

#undef PT_STREAM_COLUMNS
#undef PT_FROM_COLUMN
#undef PT_TO_COLUMN

}  // namespace PT_ISA_NS
}  // namespace pt::test
