// The shortest decimal text that reads back as the same double: std::to_chars(first, last, value)
// where the standard library has it for floating point. emscripten 3.1.6's libc++ has only the
// integer overloads, so there the same text is found with printf and strtod: the fewest
// significant digits in scientific notation ("%.*e") and the fewest decimals in fixed notation
// ("%.*f") that read back exactly, the shorter kept and fixed on a tie, as to_chars chooses.
#pragma once

#include <charconv>
#include <string>

#if !defined(__cpp_lib_to_chars)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#endif

namespace par2d::detail {

// A finite `value` as text (callers spell nan and infinities themselves).
inline std::string shortest_double(double value) {
  char buffer[400];
#if defined(__cpp_lib_to_chars)
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, value);
  if (result.ec != std::errc()) return "?";
  return std::string(buffer, result.ptr);
#else
  const auto reads_back = [&](const char* text) { return std::strtod(text, nullptr) == value; };
  std::string scientific;
  for (int digits = 0; digits <= 17; ++digits) {
    std::snprintf(buffer, sizeof buffer, "%.*e", digits, value);
    if (reads_back(buffer)) break;
  }
  scientific = buffer;  // both write at least two exponent digits: "1e+05"
  std::string fixed;
  for (int decimals = 0; decimals <= 400 - 32; ++decimals) {
    if (std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value) >= static_cast<int>(sizeof buffer)) break;
    if (reads_back(buffer)) {
      fixed = buffer;
      break;
    }
  }
  if (!fixed.empty() && fixed.size() <= scientific.size()) return fixed;
  return scientific;
#endif
}

}  // namespace par2d::detail
