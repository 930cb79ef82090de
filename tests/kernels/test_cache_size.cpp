// The L2 size the C library reports (kernels/simd/cache_size.h), against what
// the kernel lists in /sys/devices/system/cpu/cpu0/cache.
#include <gtest/gtest.h>

#include <fstream>
#include <optional>
#include <string>

#include <unistd.h>

#include "kernels/simd/cache_size.h"

namespace pt {
namespace {

/// The size of cpu0's data or unified cache of `wanted_level` in sysfs ("2048K"), if listed.
std::optional<std::size_t> sysfs_cache_bytes(int wanted_level) {
  for (int index = 0; index < 8; ++index) {
    const std::string dir = "/sys/devices/system/cpu/cpu0/cache/index" + std::to_string(index) + "/";
    std::ifstream level_file(dir + "level"), type_file(dir + "type"), size_file(dir + "size");
    int level = 0;
    std::string type, size;
    if (!(level_file >> level) || !(type_file >> type) || !(size_file >> size)) continue;
    if (level != wanted_level || type == "Instruction" || size.empty()) continue;
    std::size_t value = std::stoull(size);
    if (size.back() == 'K') value <<= 10;
    if (size.back() == 'M') value <<= 20;
    return value;
  }
  return std::nullopt;
}

TEST(CacheSize, AReportOfNoneFallsBackToTheDefault) {
  EXPECT_EQ(l2_cache_bytes_from(0), kDefaultL2CacheBytes);
  EXPECT_EQ(l2_cache_bytes_from(-1), kDefaultL2CacheBytes);
  EXPECT_EQ(l2_cache_bytes_from(2097152), 2097152u);
  EXPECT_EQ(kDefaultL2CacheBytes, 1048576u);
  EXPECT_EQ(l1_cache_bytes_from(0), kDefaultL1CacheBytes);
  EXPECT_EQ(l1_cache_bytes_from(49152), 49152u);
}

// On a real CPU (under qemu-user, CPUID is the emulated CPU's and sysfs the
// host's: tests/cli/emulated_cpus.sh leaves these two tests out).
TEST(CacheSize, L2IsWhatTheKernelListsOrTheDefault) {
  const std::size_t bytes = l2_cache_bytes();
  EXPECT_EQ(l2_cache_bytes(), bytes);  // read once
  const long reported = sysconf(_SC_LEVEL2_CACHE_SIZE);
  const std::optional<std::size_t> listed = sysfs_cache_bytes(2);
  if (reported > 0) {  // glibc on x86-64, from CPUID: the size the kernel lists
    EXPECT_EQ(bytes, std::size_t(reported));
    if (listed) { EXPECT_EQ(bytes, *listed); }
  } else {  // none reported (aarch64's glibc, often): the default
    EXPECT_EQ(bytes, kDefaultL2CacheBytes);
  }
}

TEST(CacheSize, L1IsWhatTheKernelListsOrTheDefault) {
  const std::size_t bytes = l1_data_cache_bytes();
  const long reported = sysconf(_SC_LEVEL1_DCACHE_SIZE);
  const std::optional<std::size_t> listed = sysfs_cache_bytes(1);
  if (reported > 0) {
    EXPECT_EQ(bytes, std::size_t(reported));
    if (listed) { EXPECT_EQ(bytes, *listed); }
  } else {
    EXPECT_EQ(bytes, kDefaultL1CacheBytes);
  }
}

}  // namespace
}  // namespace pt
