// Header lines compared by name in any case, one line at a time.
#include "response_head.h"

#include <cctype>

namespace pt::live {
namespace {

/// Whether `line` is a header named `name` (lower case), and then its value without surrounding blanks.
bool header_named(std::string_view line, std::string_view name, std::string_view& value) {
  if (line.size() <= name.size() || line[name.size()] != ':') return false;
  for (size_t i = 0; i < name.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(line[i])) != name[i]) return false;
  value = line.substr(name.size() + 1);
  while (!value.empty() && (value.front() == ' ' || value.front() == '\t')) value.remove_prefix(1);
  while (!value.empty() && (value.back() == ' ' || value.back() == '\t')) value.remove_suffix(1);
  return true;
}

bool is_close(std::string_view value) {
  static constexpr std::string_view kClose = "close";
  if (value.size() != kClose.size()) return false;
  for (size_t i = 0; i < kClose.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(value[i])) != kClose[i]) return false;
  return true;
}

/// Calls `line(text, with_ending)` for each line of `head` (the text without its "\r\n").
template <typename F>
void for_each_line(std::string_view head, F&& line) {
  while (!head.empty()) {
    size_t end = head.find("\r\n");
    size_t next = end == std::string_view::npos ? head.size() : end + 2;
    line(head.substr(0, end == std::string_view::npos ? head.size() : end), head.substr(0, next));
    head.remove_prefix(next);
  }
}

}  // namespace

bool head_closes_connection(std::string_view head) {
  bool closes = false;
  for_each_line(head, [&](std::string_view text, std::string_view) {
    std::string_view value;
    closes = closes || (header_named(text, "connection", value) && is_close(value));
  });
  return closes;
}

std::string closing_head(std::string_view head) {
  if (!head_closes_connection(head)) return std::string(head);
  std::string out;
  bool written = false;
  for_each_line(head, [&](std::string_view text, std::string_view whole) {
    std::string_view value;
    if (header_named(text, "connection", value) || header_named(text, "keep-alive", value)) {
      if (!written) out += "Connection: close\r\n";
      written = true;
    } else {
      out += whole;
    }
  });
  return out;
}

}  // namespace pt::live
