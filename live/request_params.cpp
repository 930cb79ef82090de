// Parameter parsing on std::from_chars: the whole text must be the number.
#include "request_params.h"

#include <charconv>
#include <cmath>

#include "http_server.h"

namespace pt::live {
namespace {

bool is_decimal_number(std::string_view s) {
  // [-]digits[.digits][e[+-]digits]: no "inf", "nan", hexadecimal, '+' or spaces.
  size_t i = 0;
  if (i < s.size() && s[i] == '-') ++i;
  size_t digits = 0;
  while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++digits;
  if (i < s.size() && s[i] == '.') {
    ++i;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++digits;
  }
  if (digits == 0) return false;
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    size_t exponent = 0;
    while (i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]))) ++i, ++exponent;
    if (exponent == 0) return false;
  }
  return i == s.size();
}

std::string number_text(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%g", v);
  return text;
}

std::string range_text(double lo, double hi) { return "a number from " + number_text(lo) + " to " + number_text(hi); }

}  // namespace

RequestParams::RequestParams(const Map& params, std::initializer_list<std::string_view> known) : params_(params) {
  for (auto it = params.begin(); it != params.end(); it = params.upper_bound(it->first)) {
    bool ok = false;
    for (std::string_view k : known) ok |= k == it->first;
    if (!ok) throw ParamError("unknown parameter \"" + log_safe(it->first, 40) + "\"");
    if (params.count(it->first) > 1) throw ParamError("parameter \"" + it->first + "\" is given more than once");
  }
}

const std::string& RequestParams::text(std::string_view name) const {
  auto it = params_.find(std::string(name));
  if (it == params_.end()) throw ParamError("missing parameter \"" + std::string(name) + "\"");
  return it->second;
}

void RequestParams::fail(std::string_view name, std::string_view must) const {
  throw ParamError(std::string(name) + ": must be " + std::string(must) + ", got \"" + log_safe(text(name), 40) + "\"");
}

double RequestParams::number(std::string_view name, double lo, double hi) const {
  const std::string& s = text(name);
  double v = 0;
  if (s.size() > 64 || !is_decimal_number(s)) fail(name, range_text(lo, hi));
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || !std::isfinite(v) || v < lo || v > hi)
    fail(name, range_text(lo, hi));
  return v;
}

int64_t RequestParams::integer(std::string_view name, int64_t lo, int64_t hi) const {
  const std::string& s = text(name);
  int64_t v = 0;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || v < lo || v > hi)
    fail(name, "an integer from " + std::to_string(lo) + " to " + std::to_string(hi));
  return v;
}

float3 RequestParams::vector(std::string_view name, float limit) const {
  const std::string& s = text(name);
  float3 out;
  size_t start = 0;
  for (int i = 0; i < 3; ++i) {
    size_t comma = s.find(',', start);
    if ((i < 2) != (comma != std::string::npos) || s.size() > 200) fail(name, "three numbers \"x,y,z\"");
    std::string_view part(s.data() + start, (i < 2 ? comma : s.size()) - start);
    double v = 0;
    auto [end, ec] = std::from_chars(part.data(), part.data() + part.size(), v);
    if (!is_decimal_number(part) || ec != std::errc() || end != part.data() + part.size() || !(std::fabs(v) <= limit))
      fail(name, "three finite numbers \"x,y,z\" of magnitude at most " + number_text(limit));
    out[i] = float(v);
    start = comma + 1;
  }
  return out;
}

size_t RequestParams::choice(std::string_view name, std::span<const char* const> names) const {
  const std::string& s = text(name);
  for (size_t i = 0; i < names.size(); ++i)
    if (s == names[i]) return i;
  std::string list;
  for (const char* n : names) list += (list.empty() ? "" : ", ") + std::string(n);
  fail(name, "one of " + list);
}

std::string RequestParams::file_name(std::string_view name, std::string_view extension) const {
  const std::string& s = text(name);
  bool ok = s.size() > extension.size() && s.size() <= 64 && s[0] != '.' && s[0] != '-' && s.ends_with(extension);
  for (char c : s) ok &= std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
  if (!ok)
    fail(name, "a file name of 1-64 letters, digits, '_', '-' and '.', not starting with '.' or '-', ending in " +
                   std::string(extension) + " (no directories)");
  return s;
}

}  // namespace pt::live
