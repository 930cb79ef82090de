// Little helpers of the binary files this renderer writes (checkpoints, tile
// sets): appending and taking plain values, the FNV-1a checksum, and the
// frame both files share: an 8-byte magic, the body, and the checksum of both.
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

/// Appends the checksum that closes a frame begun with the magic.
inline void close_frame(std::string& out) { put(out, fnv1a(out.data(), out.size())); }

/// The body of `data` framed as magic, body, fnv1a(magic + body). Throws
/// bad("bad header" + header_hint) when the magic is missing, bad("checksum
/// mismatch") when the checksum differs.
template <class Bad>
std::string_view frame_body(const std::string& data, const char (&magic)[8], Bad bad, const char* header_hint = "") {
  if (data.size() < sizeof magic + 8 || std::memcmp(data.data(), magic, sizeof magic) != 0)
    throw bad(std::string("bad header") + header_hint);
  uint64_t stored = 0;
  std::memcpy(&stored, data.data() + data.size() - 8, 8);
  if (fnv1a(data.data(), data.size() - 8) != stored) throw bad("checksum mismatch");
  return std::string_view(data.data() + sizeof magic, data.size() - sizeof magic - 8);
}

}  // namespace pt
