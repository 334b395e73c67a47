#pragma once
// Internal: real numbers as messages print them.
//
// std::to_string prints a double with six fixed decimals, so the figures a message is about (a
// relative residual of 3e-7 against a tolerance of 1e-8, a merge tolerance of 1e-9) all read
// "0.000000". Messages print them with three significant digits instead: number_text in exponent
// form where that is shorter ("3e-07", "0.25", "1.23e+05", "nan", "inf"), scientific_text always
// in exponent form, for figures compared across orders of magnitude such as a solver's residual
// and its tolerance ("2.50e-01 (tolerance 1.00e-08)").

#include <cstdio>
#include <string>

namespace harmonia::detail {

[[nodiscard]] inline std::string number_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

[[nodiscard]] inline std::string scientific_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.2e", value);
  return buffer;
}

}  // namespace harmonia::detail
