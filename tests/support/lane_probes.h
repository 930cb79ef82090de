// The lane kernels and SIMD primitives of one instruction-set level, run over
// plain arrays (lane_probes_isa.cpp is compiled once per level), so that tests
// compiled once can check the level in use against the scalar instantiation.
#pragma once

#include <cstddef>
#include <cstdint>

#include "kernels/math/bbox.h"
#include "kernels/simd/isa.h"
#include "support/stream_columns.h"

namespace pt::test {

struct LaneProbes {
  Isa isa;
  size_t lanes;  ///< K; array lengths below are whole multiples of it where noted
  /// pixel_key(seed, pixels[i]) -> keys[i] and random_float(key, sample_key(samples[i]), dim_key) -> values[i];
  /// n a multiple of K.
  void (*random_numbers)(uint32_t seed, const uint32_t* pixels, const uint32_t* samples, uint32_t dim_key, size_t n,
                         uint32_t* keys, float* values);
  /// The Sobol sampler of (seed, pixels[i], samples[i]): get2d(bounce, dim) -> (u[i], v[i]) and
  /// get1d(bounce, dim + 2) -> w[i]; n a multiple of K.
  void (*sobol_points)(uint32_t seed, const uint32_t* pixels, const uint32_t* samples, uint32_t bounce, uint32_t dim,
                       size_t n, float* u, float* v, float* w);
  /// Warp `which` (0 uniform hemisphere, 1 cosine hemisphere, 2 uniform sphere) of (a[i], b[i]); n a multiple of K.
  void (*warp)(int which, const float* a, const float* b, size_t n, float* x, float* y, float* z);
  /// lane_mask(lanes_of_mask(bits)).
  uint32_t (*mask_round_trip)(uint32_t bits);
  /// lane_mask of as_float_mask(a[i] == b[i]) over K lanes (integer compare, any bit patterns).
  uint32_t (*equal_uint_lanes)(const uint32_t* a, const uint32_t* b);
  /// lane_mask of as_float_mask(as_int_mask(x[i] < y[i])) over K lanes.
  uint32_t (*less_through_int_mask)(const float* x, const float* y);
  /// store_compressed of K values: out[0..popcount(mask)) = the values of the set lanes; out has room for K.
  void (*compress)(const float* in, uint32_t mask, float* out);
  /// out[i] = base[index[i]] over K lanes.
  void (*gather)(const float* base, const int32_t* index, float* out);
  /// gather_records3 over K lanes: out[c * K + i] = base[3 * index[i] + c], base holding `records` records
  /// (floats, and the same as 32-bit words).
  void (*gather_records3)(const float* base, const int32_t* index, int32_t records, float* out);
  void (*gather_int_records3)(const int32_t* base, const int32_t* index, int32_t records, int32_t* out);
  /// Smallest and largest of K values.
  float (*reduce_min)(const float* in);
  float (*reduce_max)(const float* in);
  /// Stream compaction as the stages do it (soa_lanes.h): for each chunk c of
  /// K items of `in`, the lanes set in masks[c] are appended to the result.
  /// Rays and shadow rays as columns (stream_columns.h).
  StreamColumns (*compact_rays)(const StreamColumns& in, const uint32_t* masks);
  StreamColumns (*compact_shadows)(const StreamColumns& in, const uint32_t* masks);
  /// wf::sort_by_hit_point at this level, of a ray queue and its hits as
  /// columns, with one scratch (wf::HitPointOrder) kept from call to call as
  /// a thread's wave buffers keep theirs.
  void (*sort_by_hit_point)(const BBox& bounds, StreamColumns& rays, StreamColumns& hits);
};

/// The probes of a compiled level (IsaError otherwise).
const LaneProbes& lane_probes(Isa isa);

}  // namespace pt::test
