// The cache sizes this CPU reports (cache_size.h).
#include "cache_size.h"

#include <unistd.h>

namespace pt {

std::size_t l2_cache_bytes() {
  static const std::size_t bytes = l2_cache_bytes_from(sysconf(_SC_LEVEL2_CACHE_SIZE));
  return bytes;
}

std::size_t l1_data_cache_bytes() {
  static const std::size_t bytes = l1_cache_bytes_from(sysconf(_SC_LEVEL1_DCACHE_SIZE));
  return bytes;
}

}  // namespace pt
