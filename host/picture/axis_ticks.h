#pragma once
// Internal: the ticks of a plot axis: round values (1, 2 or 5 times a power of ten apart) that
// cover a range, the range widened outwards to whole steps, and their labels.

#include <string>
#include <vector>

namespace harmonia::detail {

struct AxisTicks {
  double low = 0.0;  // The axis runs from low to high, both ticks.
  double high = 1.0;
  std::vector<double> values;  // low, low + step, ..., high.
  std::vector<std::string> labels;
};

// About `target_count` steps over [low, high] (low < high, both finite). A value within 1e-9
// steps of a tick counts as on it, so that rounding does not add an empty step.
[[nodiscard]] AxisTicks axis_ticks(double low, double high, int target_count);

}  // namespace harmonia::detail
