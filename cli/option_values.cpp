// parse_integer, parse_number and parse_choice on std::from_chars.
#include "option_values.h"

#include <charconv>
#include <cmath>

#include "io/scene_error.h"

namespace pt::cli {
namespace {

std::string quoted(std::string_view text) {
  std::string q(1, '"');  // not "\"" + string: GCC 12 reports a false -Wrestrict on that
  q += printable_line(excerpt(text));
  q += '"';
  return q;
}

std::string prefix(std::string_view flag, std::string_view what) {
  return std::string(flag) + ": " + std::string(what) + " must be ";
}

}  // namespace

ValueError parse_integer(std::string_view flag, std::string_view what, std::string_view text, int64_t lo, int64_t hi,
                         int64_t& out) {
  std::string range = "an integer from " + std::to_string(lo) + " to " + std::to_string(hi);
  int64_t v = 0;
  const char* last = text.data() + text.size();
  auto [end, ec] = std::from_chars(text.data(), last, v);
  bool whole = !text.empty() && end == last;
  if (!whole || ec != std::errc() || v < lo || v > hi) return prefix(flag, what) + range + ", got " + quoted(text);
  out = v;
  return {};
}

ValueError parse_number(std::string_view flag, std::string_view what, std::string_view text, std::string_view range,
                        bool (*accept)(double), double& out) {
  double v = 0.0;
  const char* last = text.data() + text.size();
  auto [end, ec] = std::from_chars(text.data(), last, v, std::chars_format::general);
  if (text.empty() || end != last || ec != std::errc() || !std::isfinite(v) || !accept(v))
    return prefix(flag, what) + std::string(range) + ", got " + quoted(text);
  out = v;
  return {};
}

ValueError parse_choice(std::string_view flag, std::string_view what, std::string_view text,
                        std::span<const char* const> names, size_t& out) {
  for (size_t i = 0; i < names.size(); ++i)
    if (text == names[i]) {
      out = i;
      return {};
    }
  std::string list;
  for (size_t i = 0; i < names.size(); ++i) list += (i ? ", " : "") + std::string(names[i]);
  return std::string(flag) + ": unknown " + std::string(what) + " " + quoted(text) + " (one of: " + list + ")";
}

}  // namespace pt::cli
