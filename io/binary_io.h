// Little helpers of the binary files this renderer writes (checkpoints, tile
// sets): appending and taking plain values, and the FNV-1a checksum.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>

namespace pt {

inline uint64_t fnv1a(const void* data, size_t n, uint64_t h = 0xcbf29ce484222325ull) {
  const unsigned char* p = static_cast<const unsigned char*>(data);
  for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001b3ull;
  return h;
}

template <class T>
void put(std::string& out, const T& v) {
  out.append(reinterpret_cast<const char*>(&v), sizeof v);
}

/// Takes sizeof(T) bytes off the front of `in`; false if there are fewer.
template <class T>
bool take(std::string_view& in, T& v) {
  if (in.size() < sizeof v) return false;
  std::memcpy(&v, in.data(), sizeof v);
  in.remove_prefix(sizeof v);
  return true;
}

}  // namespace pt
