// Strict decimal number parsing for the text formats io/ reads (COLLADA
// number lists, camera settings files): one token must be exactly one number.
#pragma once

#include <string_view>

namespace pt {

enum class Number { kOk, kNotANumber, kOutOfRange };

/// Parses the whole of `token` as a decimal float with an optional sign ('+'
/// or '-'); no hexadecimal, no trailing characters. "inf" and "nan" parse
/// (kOk, non-finite value): callers that need finite numbers check. A value
/// too small for a float (1e-50) becomes 0; one too large is kOutOfRange.
Number parse_float(std::string_view token, float& value);

}  // namespace pt
