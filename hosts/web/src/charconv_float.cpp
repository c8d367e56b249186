// The float overloads of charconv_float.h over the C library, which in
// emscripten has only the "C" locale, so the decimal point is always '.'.
#include "charconv_float.h"

#if !defined(__cpp_lib_to_chars)
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <system_error>

namespace {

// Fewest significant digits (1 to 17) that read back to `value`.
template <class T>
std::to_chars_result ShortestText(char* first, char* last, T value) {
  char text[40];
  int length = 0;
  if (std::isnan(value)) {
    length = std::snprintf(text, sizeof text, "%s", std::signbit(value) ? "-nan" : "nan");
  } else if (std::isinf(value)) {
    length = std::snprintf(text, sizeof text, "%s", value < 0 ? "-inf" : "inf");
  } else {
    for (int digits = 1; digits <= 17; ++digits) {
      length = std::snprintf(text, sizeof text, "%.*g", digits, static_cast<double>(value));
      if (static_cast<T>(std::strtod(text, nullptr)) == value) break;
    }
  }
  if (length <= 0 || length > last - first) return {last, std::errc::value_too_large};
  std::memcpy(first, text, static_cast<std::size_t>(length));
  return {first + length, std::errc{}};
}

template <class T>
std::from_chars_result ParseText(const char* first, const char* last, T& value) {
  char text[128];
  const std::size_t length = static_cast<std::size_t>(last - first);
  const bool starts_well = length > 0 && (first[0] == '-' || first[0] == '.' || first[0] == 'i' ||
                                          first[0] == 'I' || first[0] == 'n' || first[0] == 'N' ||
                                          (first[0] >= '0' && first[0] <= '9'));
  // Hex ("0x..."), which strtod reads and from_chars' general format does not.
  const char* digits = first[0] == '-' ? first + 1 : first;
  const bool hex = last - digits >= 2 && digits[0] == '0' && (digits[1] == 'x' || digits[1] == 'X');
  if (!starts_well || hex) return {first, std::errc::invalid_argument};
  const std::size_t copied = length < sizeof text - 1 ? length : sizeof text - 1;
  std::memcpy(text, first, copied);
  text[copied] = '\0';
  char* end = nullptr;
  errno = 0;
  const double parsed = std::strtod(text, &end);
  if (end == text) return {first, std::errc::invalid_argument};
  const char* stop = first + (end - text);
  const T narrowed = static_cast<T>(parsed);
  if (errno == ERANGE || (std::isinf(narrowed) && !std::isinf(parsed))) return {stop, std::errc::result_out_of_range};
  value = narrowed;
  return {stop, std::errc{}};
}

}  // namespace

namespace std {
to_chars_result to_chars(char* first, char* last, float value) { return ShortestText(first, last, value); }
to_chars_result to_chars(char* first, char* last, double value) { return ShortestText(first, last, value); }
from_chars_result from_chars(const char* first, const char* last, float& value) {
  return ParseText(first, last, value);
}
from_chars_result from_chars(const char* first, const char* last, double& value) {
  return ParseText(first, last, value);
}
}  // namespace std
#endif
