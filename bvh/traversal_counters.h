// Work counters of a ray query: inner nodes visited and primitives tested.
// Traversals are templates over the counter type; NoCounters compiles every
// increment away, so the fast path carries no counting code.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"

namespace pt {

/// 16 bytes. Accumulates over any number of queries.
struct TraversalCounters {
  uint64_t nodes = 0;       ///< inner nodes whose child boxes were tested
  uint64_t primitives = 0;  ///< triangles (valid block lanes) and spheres tested

  static constexpr bool kEnabled = true;
  void node() { ++nodes; }
  void nodes_tested(uint64_t n) { nodes += n; }
  void primitives_tested(uint32_t n) { primitives += n; }
  TraversalCounters& operator+=(const TraversalCounters& o) {
    nodes += o.nodes;
    primitives += o.primitives;
    return *this;
  }
};
static_assert(sizeof(TraversalCounters) == 16);

inline namespace PT_ISA_NS {
/// The fast path's counters: nothing.
struct NoCounters {
  static constexpr bool kEnabled = false;
  void node() {}
  void nodes_tested(uint64_t) {}
  void primitives_tested(uint32_t) {}
};

}  // namespace PT_ISA_NS
}  // namespace pt
