#pragma once
// Internal: a real number as messages print it.
//
// std::to_string prints a double with six fixed decimals, so the figures a message is about (a
// relative residual of 3e-7 against a tolerance of 1e-8, a merge tolerance of 1e-9) all read
// "0.000000". Messages print them with three significant digits instead, in exponent form where
// that is shorter ("3e-07", "0.25", "1.23e+05", "nan", "inf").

#include <cstdio>
#include <string>

namespace harmonia::detail {

[[nodiscard]] inline std::string number_text(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g", value);
  return buffer;
}

}  // namespace harmonia::detail
