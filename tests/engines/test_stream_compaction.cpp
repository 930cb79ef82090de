// Stream compaction carries every field a stream declares: each field of
// every item gets a distinct value, the queues the stages compact (rays,
// shadow rays) are compacted under random lane masks at the level in use, and
// each survivor must arrive with all its fields, in order. The field lists
// are the streams' own (streams.h), so a field added there is checked here.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "kernels/simd/isa.h"
#include "support/lane_probes.h"
#include "support/stream_columns.h"
#include "wavefront/streams.h"

namespace pt {
namespace {

/// Distinct values: field f of item i holds 100000 f + i.
#define PT_FILL_FIELD(T, name)                                                   \
  for (size_t i = 0; i < n; ++i) q.name[i] = static_cast<T>(100000 * field + i); \
  ++field;
#define PT_CHECK_FIELD(T, name)            \
  for (size_t k = 0; k < kept.size(); ++k) \
    ASSERT_EQ(out.name[k], in.name[kept[k]]) << #name << " of survivor " << k << " (item " << kept[k] << ")";

template <class Queue>
std::vector<uint32_t> random_masks(size_t n, size_t lanes, std::mt19937& rng) {
  std::vector<uint32_t> masks((n + lanes - 1) / lanes);
  for (size_t c = 0; c < masks.size(); ++c) {
    masks[c] = static_cast<uint32_t>(rng()) & lanes_below(lanes);
    if (c % 7 == 0) masks[c] = 0;
    if (c % 11 == 0) masks[c] = lanes_below(lanes);
    size_t valid = std::min(lanes, n - c * lanes);  // lanes past the end hold no item
    masks[c] &= lanes_below(valid);
  }
  return masks;
}

std::vector<size_t> survivors(const std::vector<uint32_t>& masks, size_t lanes) {
  std::vector<size_t> kept;
  for (size_t c = 0; c < masks.size(); ++c)
    for (size_t l = 0; l < lanes; ++l)
      if (masks[c] >> l & 1) kept.push_back(c * lanes + l);
  return kept;
}

/// Fills a queue of n items with distinct values, compacts it with `compact`
/// under random masks and checks every field of every survivor (`check`).
template <class Queue, class Fill, class Compact, class Check>
void expect_compaction_keeps_every_field(uint32_t seed, Fill&& fill, Compact&& compact, Check&& check) {
  const size_t lanes = test::lane_probes(active_isa()).lanes;
  std::mt19937 rng(seed);
  for (size_t n : {size_t(1), lanes, 3 * lanes + 1, size_t(1000)}) {
    Queue in, out;
    in.reserve(n);
    in.size = n;
    fill(in, n);
    std::vector<uint32_t> masks = random_masks<Queue>(n, lanes, rng);
    test::from_columns(compact(test::columns_of(in), masks.data()), out);
    std::vector<size_t> kept = survivors(masks, lanes);
    ASSERT_EQ(out.size, kept.size());
    check(in, out, kept);
  }
}

TEST(StreamCompaction, EveryFieldOfARayReachesTheNextQueue) {
  expect_compaction_keeps_every_field<wf::RayQueue>(
      3,
      [](wf::RayQueue& q, size_t n) {
        uint32_t field = 0;
        PT_RAY_FIELDS(PT_FILL_FIELD)
      },
      test::lane_probes(active_isa()).compact_rays,
      [](const wf::RayQueue& in, const wf::RayQueue& out, const std::vector<size_t>& kept) {
        PT_RAY_FIELDS(PT_CHECK_FIELD)
      });
}

TEST(StreamCompaction, EveryFieldOfAShadowRayReachesTheNextQueue) {
  expect_compaction_keeps_every_field<wf::ShadowQueue>(
      4,
      [](wf::ShadowQueue& q, size_t n) {
        uint32_t field = 0;
        PT_SHADOW_FIELDS(PT_FILL_FIELD)
      },
      test::lane_probes(active_isa()).compact_shadows,
      [](const wf::ShadowQueue& in, const wf::ShadowQueue& out, const std::vector<size_t>& kept) {
        PT_SHADOW_FIELDS(PT_CHECK_FIELD)
      });
}

}  // namespace
}  // namespace pt
