// An allocator for the big BVH arrays: blocks of 1 MiB and more are 2 MiB
// aligned and offered to the kernel for transparent huge pages
// (madvise(MADV_HUGEPAGE)), so that random accesses across a large tree miss
// the TLB far less often (Embree does the same). Smaller blocks, or systems
// without huge pages, get ordinary aligned memory.
#pragma once

#include <cstddef>
#include <cstdlib>
#include <new>

#include <sys/mman.h>

namespace pt {

template <class T>
struct HugePageAllocator {
  using value_type = T;
  static constexpr std::size_t kHugePage = std::size_t(2) << 20;
  static constexpr std::size_t kThreshold = std::size_t(1) << 20;

  HugePageAllocator() = default;
  template <class U>
  HugePageAllocator(const HugePageAllocator<U>&) {}

  /// Bytes an allocation of n elements takes: blocks of kThreshold and more
  /// are rounded up to whole huge pages (all of which become resident).
  static constexpr std::size_t allocated_bytes(std::size_t n) {
    std::size_t bytes = n * sizeof(T);
    return bytes < kThreshold ? bytes : (bytes + kHugePage - 1) / kHugePage * kHugePage;
  }

  T* allocate(std::size_t n) {
    std::size_t bytes = n * sizeof(T);
    if (bytes < kThreshold) return static_cast<T*>(::operator new(bytes, std::align_val_t(alignof(T))));
    std::size_t rounded = allocated_bytes(n);
    void* p = std::aligned_alloc(kHugePage, rounded);
    if (!p) throw std::bad_alloc();
    madvise(p, rounded, MADV_HUGEPAGE);  // a hint: failure leaves ordinary pages
    return static_cast<T*>(p);
  }
  void deallocate(T* p, std::size_t n) {
    if (n * sizeof(T) < kThreshold) ::operator delete(p, std::align_val_t(alignof(T)));
    else std::free(p);
  }
  template <class U>
  bool operator==(const HugePageAllocator<U>&) const {
    return true;
  }
};

}  // namespace pt
