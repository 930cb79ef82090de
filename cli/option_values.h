// Strict conversion of command-line values. Only plain decimal integers and
// finite decimal numbers are accepted (not "0x10", "010" read as octal, "1e3"
// for an integer, "4x" or "nan"), and every failure is one line naming the
// flag, what the value means, the accepted range and the text given.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace pt::cli {

/// The result of one conversion: the error message, empty on success.
using ValueError = std::string;

/// Sets `out`, or returns "FLAG: WHAT must be an integer from LO to HI, got "TEXT"".
ValueError parse_integer(std::string_view flag, std::string_view what, std::string_view text, int64_t lo, int64_t hi,
                         int64_t& out);

/// Sets `out` if `text` is a finite decimal number for which accept(value)
/// holds; otherwise returns "FLAG: WHAT must be RANGE, got "TEXT"".
ValueError parse_number(std::string_view flag, std::string_view what, std::string_view text, std::string_view range,
                        bool (*accept)(double), double& out);

/// Sets `out` to the index of `text` in `names`; otherwise returns
/// "FLAG: unknown WHAT "TEXT" (one of: a, b, c)".
ValueError parse_choice(std::string_view flag, std::string_view what, std::string_view text,
                        std::span<const char* const> names, size_t& out);

}  // namespace pt::cli
