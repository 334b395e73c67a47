// Round tick values: the step is 1, 2 or 5 times a power of ten, the one nearest (on a log scale)
// to the range over the asked number of steps (Heckbert's "nice numbers", Graphics Gems, 1990);
// labels carry as many decimals as the step needs.
#include "picture/axis_ticks.h"

#include <algorithm>
#include <cmath>

#include "picture/svg_markup.h"

namespace harmonia::detail {

AxisTicks axis_ticks(double low, double high, int target_count) {
  constexpr double kOnTick = 1e-9;
  const double raw_step = (high - low) / std::max(target_count, 1);
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw_step) + kOnTick));
  const double fraction = raw_step / magnitude;
  const double multiple = fraction < 1.5 ? 1.0 : fraction < 3.0 ? 2.0 : fraction < 7.0 ? 5.0 : 10.0;
  const double step = multiple * magnitude;
  const double first = std::floor(low / step + kOnTick);
  const double last = std::ceil(high / step - kOnTick);
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + kOnTick)));

  AxisTicks ticks;
  ticks.low = first * step;
  ticks.high = last * step;
  for (double k = first; k <= last; k += 1.0) {
    const double value = k * step;  // A multiple, not a running sum: no drift along the axis.
    ticks.values.push_back(value);
    ticks.labels.push_back(fixed_number(value, decimals));
  }
  return ticks;
}

}  // namespace harmonia::detail
