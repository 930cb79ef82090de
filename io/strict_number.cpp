// parse_float on std::from_chars (locale-independent).
#include "strict_number.h"

#include <charconv>
#include <cmath>

namespace pt {

Number parse_float(std::string_view token, float& value) {
  std::string_view s = token;
  if (!s.empty() && s.front() == '+') {
    s.remove_prefix(1);
    if (!s.empty() && s.front() == '-') return Number::kNotANumber;
  }
  const char* last = s.data() + s.size();
  auto [end, ec] = std::from_chars(s.data(), last, value);
  if (ec == std::errc::result_out_of_range) {
    // from_chars reports underflow as out of range too; retry in double to tell them apart.
    double d = 0.0;
    auto [dend, dec] = std::from_chars(s.data(), last, d);
    if (dec == std::errc() && dend == last && std::fabs(d) < 1.0) {
      value = static_cast<float>(d);
      return Number::kOk;
    }
    return end == last ? Number::kOutOfRange : Number::kNotANumber;
  }
  return ec == std::errc() && end == last ? Number::kOk : Number::kNotANumber;
}

}  // namespace pt
