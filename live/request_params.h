// Strict reading of a request's query parameters: only the names a route
// knows, each at most once, and each value a whole decimal number in range,
// a vector "x,y,z", one of a list of names, or a file name of a fixed form.
// Anything else throws ParamError with a one-line message naming the
// parameter, what it must be and what was given; the route answers 400 with it.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "kernels/math/vec3.h"

namespace pt::live {

struct ParamError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

class RequestParams {
 public:
  using Map = std::multimap<std::string, std::string>;

  /// Throws for a name not in `known` and for a name given twice.
  RequestParams(const Map& params, std::initializer_list<std::string_view> known);

  bool has(std::string_view name) const { return params_.count(std::string(name)) > 0; }
  /// A finite decimal number in [lo, hi].
  double number(std::string_view name, double lo, double hi) const;
  /// A decimal integer in [lo, hi] (no sign but '-', no exponent, no fraction).
  int64_t integer(std::string_view name, int64_t lo, int64_t hi) const;
  /// Three finite numbers "x,y,z", each of magnitude at most `limit`.
  float3 vector(std::string_view name, float limit) const;
  /// The index of the value in `names`.
  size_t choice(std::string_view name, std::span<const char* const> names) const;
  /// A file name: 1-64 characters of [A-Za-z0-9_.-], starting with a letter, digit or '_' (not '.': hidden;
  /// not '-': a command line would read it as an option), ending in `extension`.
  std::string file_name(std::string_view name, std::string_view extension) const;

 private:
  const std::string& text(std::string_view name) const;
  [[noreturn]] void fail(std::string_view name, std::string_view must) const;

  const Map& params_;
};

}  // namespace pt::live
