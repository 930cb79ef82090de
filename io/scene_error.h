// The one exception type of io/: a bad scene, camera file or output path. Its
// message is a single line naming the file and the element, ready to print:
// the constructor escapes control characters (a newline in a file name or in
// an attribute value cannot split it), and excerpt() keeps quoted file
// content short.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

namespace pt {

/// `text` with every control character (bytes 0-31 and 127) written as \xNN.
inline std::string printable_line(std::string_view text) {
  static constexpr char kHex[] = "0123456789abcdef";
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    auto u = static_cast<unsigned char>(c);
    if (u >= 0x20 && u != 0x7f) {
      out += c;
    } else {
      out += "\\x";
      out += kHex[u >> 4];
      out += kHex[u & 15];
    }
  }
  return out;
}

/// At most `max_chars` bytes of `text`, with "..." appended when cut: for
/// quoting names, values and tokens from a file in a message.
inline std::string excerpt(std::string_view text, size_t max_chars = 32) {
  return text.size() <= max_chars ? std::string(text) : std::string(text.substr(0, max_chars)) + "...";
}

class InputError : public std::runtime_error {
 public:
  explicit InputError(std::string_view what) : std::runtime_error(printable_line(what)) {}
};

}  // namespace pt
