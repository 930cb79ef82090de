// LaneProbes of one instruction-set level (compiled once per level).
#include "kernels/transport/path_sampler.h"
#include "kernels/math/random.h"
#include "kernels/math/sampling.h"
#include "kernels/simd/simd.h"
#include "support/lane_probes.h"
#include "wavefront/hit_point_order.h"
#include "wavefront/soa_lanes.h"

namespace pt::test {
namespace {

void random_numbers(uint32_t seed, const uint32_t* pixels, const uint32_t* samples, uint32_t dim_key, size_t n,
                    uint32_t* keys, float* values) {
  for (size_t i = 0; i < n; i += kLanes) {
    vuintK pk = pixel_key<vuintK>(seed, vuintK::load_unaligned(pixels + i));
    vuintK sk = sample_key<vuintK>(vuintK::load_unaligned(samples + i));
    pk.store_unaligned(keys + i);
    random_float<vuintK, vfloatK>(pk, sk, dim_key).store_unaligned(values + i);
  }
}

void sobol_points(uint32_t seed, const uint32_t* pixels, const uint32_t* samples, uint32_t bounce, uint32_t dim,
                  size_t n, float* u, float* v, float* w) {
  const RenderSettings rs{.sampler = PixelSampler::kSobol, .seed = seed};
  for (size_t i = 0; i < n; i += kLanes) {
    PathSamplerT<vuintK, vfloatK> ps(rs, vuintK::load_unaligned(pixels + i), vuintK::load_unaligned(samples + i));
    vfloatK a, b;
    ps.get2d(bounce, dim, a, b);
    a.store_unaligned(u + i);
    b.store_unaligned(v + i);
    ps.get1d(bounce, dim + 2).store_unaligned(w + i);
  }
}

void warp(int which, const float* a, const float* b, size_t n, float* x, float* y, float* z) {
  for (size_t i = 0; i < n; i += kLanes) {
    vfloatK va = vfloatK::load_unaligned(a + i), vb = vfloatK::load_unaligned(b + i);
    Vec3T<vfloatK> v = which == 0   ? sample_uniform_hemisphere(va, vb)
                       : which == 1 ? sample_cosine_hemisphere(va, vb)
                                    : sample_uniform_sphere(va, vb);
    v.x.store_unaligned(x + i);
    v.y.store_unaligned(y + i);
    v.z.store_unaligned(z + i);
  }
}

uint32_t mask_round_trip(uint32_t bits) { return lane_mask(lanes_of_mask(bits)); }

uint32_t equal_uint_lanes(const uint32_t* a, const uint32_t* b) {
  return lane_mask(as_float_mask(vuintK::load_unaligned(a) == vuintK::load_unaligned(b)));
}

uint32_t less_through_int_mask(const float* x, const float* y) {
  vbooliK m = as_int_mask(vfloatK::load_unaligned(x) < vfloatK::load_unaligned(y));
  return lane_mask(as_float_mask(m));
}

void compress(const float* in, uint32_t mask, float* out) { store_compressed(out, mask, vfloatK::load_unaligned(in)); }

void gather_floats(const float* base, const int32_t* index, float* out) {
  gather(base, vintK::load_unaligned(index)).store_unaligned(out);
}

template <class T, class V>
void records3(const T* base, const int32_t* index, int32_t records, T* out) {
  V c[3];
  gather_records3(base, vintK::load_unaligned(index), records, c);
  for (size_t k = 0; k < 3; ++k) c[k].store_unaligned(out + k * kLanes);
}

float min_of(const float* in) { return reduce_min_k(vfloatK::load_unaligned(in)); }
float max_of(const float* in) { return reduce_max_k(vfloatK::load_unaligned(in)); }

template <class Stream>
StreamColumns compact(const StreamColumns& columns, const uint32_t* masks) {
  Stream in, out;
  from_columns(columns, in);
  for (size_t i0 = 0; i0 < in.size; i0 += kLanes) wf::append_lanes(out, masks[i0 / kLanes], wf::load_lanes(in, i0));
  return columns_of(out);
}

void sort_by_hit_point(const BBox& bounds, StreamColumns& ray_columns, StreamColumns& hit_columns) {
  static wf::HitPointOrder scratch;
  wf::RayQueue rays;
  wf::HitQueue hits;
  from_columns(ray_columns, rays);
  from_columns(hit_columns, hits);
  wf::sort_by_hit_point(bounds, rays, hits, scratch);
  ray_columns = columns_of(rays);
  hit_columns = columns_of(hits);
}

}  // namespace
}  // namespace pt::test

namespace pt {
inline namespace PT_ISA_NS {
extern const test::LaneProbes kLaneProbes;
const test::LaneProbes kLaneProbes = {
    .isa = PT_ISA,
    .lanes = kLanes,
    .random_numbers = test::random_numbers,
    .sobol_points = test::sobol_points,
    .warp = test::warp,
    .mask_round_trip = test::mask_round_trip,
    .equal_uint_lanes = test::equal_uint_lanes,
    .less_through_int_mask = test::less_through_int_mask,
    .compress = test::compress,
    .gather = test::gather_floats,
    .gather_records3 = test::records3<float, vfloatK>,
    .gather_int_records3 = test::records3<int32_t, vintK>,
    .reduce_min = test::min_of,
    .reduce_max = test::max_of,
    .compact_rays = test::compact<wf::RayQueue>,
    .compact_shadows = test::compact<wf::ShadowQueue>,
    .sort_by_hit_point = test::sort_by_hit_point,
};
}  // namespace PT_ISA_NS
}  // namespace pt
