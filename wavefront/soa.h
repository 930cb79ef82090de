// Structure-of-arrays streams whose fields are declared once, as an X-macro
// list, and expanded into 64-byte-aligned arrays (padded to the widest SIMD
// lane count, so kernels never mask tails at any level) and a one-item
// struct. Every queue and the path state are built with PT_SOA_STREAM; their
// K-wide views are generated from the same lists (soa_lanes.h).
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <new>
#include <vector>

#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/simd.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

template <class T>
struct AlignedAllocator {
  using value_type = T;
  AlignedAllocator() = default;
  template <class U>
  AlignedAllocator(const AlignedAllocator<U>&) {}
  T* allocate(size_t n) { return static_cast<T*>(::operator new (n * sizeof(T), std::align_val_t{64})); }
  void deallocate(T* p, size_t) { ::operator delete (p, std::align_val_t{64}); }
  template <class U>
  bool operator==(const AlignedAllocator<U>&) const {
    return true;
  }
};

template <class T>
using AlignedVector = std::vector<T, AlignedAllocator<T>>;

/// n rounded up to a whole number of the widest batches (kMaxLanes).
inline size_t round_up_to_lanes(size_t n) { return (n + kMaxLanes - 1) / kMaxLanes * kMaxLanes; }

}  // namespace PT_ISA_NS
}  // namespace pt::wf

#define PT_SOA_ARRAY(type, name) ::pt::wf::AlignedVector<type> name;
#define PT_SOA_ITEM_FIELD(type, name) type name;
#define PT_SOA_RESIZE(type, name) name.resize(n);
#define PT_SOA_BYTES(type, name) +name.capacity() * sizeof(type)

/// Declares, inside a struct, the arrays of FIELDS, `Item` (one element as
/// plain fields: its size is the stream's bytes per item), size/capacity,
/// reserve(), clear() and bytes(). Lane views: soa_lanes.h.
#define PT_SOA_STREAM(FIELDS)                                                      \
  FIELDS(PT_SOA_ARRAY)                                                             \
  struct Item {                                                                    \
    FIELDS(PT_SOA_ITEM_FIELD)                                                      \
  };                                                                               \
  size_t size = 0;                                                                 \
  size_t capacity = 0;                                                             \
  /** Room for n items (keeping the current ones); arrays are padded to whole   */ \
  /** SIMD batches. */                                                             \
  void reserve(size_t n_items) {                                                   \
    size_t n = ::pt::wf::round_up_to_lanes(n_items);                               \
    if (n > capacity) {                                                            \
      FIELDS(PT_SOA_RESIZE)                                                        \
      capacity = n;                                                                \
    }                                                                              \
  }                                                                                \
  void clear() { size = 0; }                                                       \
  size_t bytes() const { return 0 FIELDS(PT_SOA_BYTES); }
