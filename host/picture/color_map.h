#pragma once
// Internal: the colours of a distortion picture and the colour bar that explains them. Undistorted
// is white, so that in a good map every coloured patch is a problem worth seeing; the background is
// a light grey that sets it off.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace harmonia::detail {

struct Rgb {
  std::uint8_t red = 0;
  std::uint8_t green = 0;
  std::uint8_t blue = 0;

  friend bool operator==(const Rgb&, const Rgb&) = default;
};

inline constexpr Rgb kBackground{228, 230, 234};
inline constexpr Rgb kEdgeColor{96, 96, 96};
inline constexpr Rgb kFlippedFill{0, 0, 0};
inline constexpr Rgb kFlippedOutline{255, 0, 255};   // magenta
inline constexpr Rgb kUndefinedFill{160, 160, 160};  // NaN: a face with no meaningful value
inline constexpr Rgb kLegendColor{0, 0, 0};

// The curves of a distortion plot, one colour per layout: Tableau 10, ten hues that stay apart on
// white and for most colour-blind readers.
inline constexpr std::array<Rgb, 10> kLayoutColors = {{{78, 121, 167},
                                                      {242, 142, 43},
                                                      {225, 87, 89},
                                                      {118, 183, 178},
                                                      {89, 161, 79},
                                                      {237, 201, 72},
                                                      {176, 122, 161},
                                                      {255, 157, 167},
                                                      {156, 117, 95},
                                                      {186, 176, 172}}};

// sigma1/sigma2 at which the conformal colour saturates, and |log area ratio| at which the area
// colour saturates (a factor of 4 either way).
inline constexpr double kConformalSaturation = 4.0;
inline const double kAreaSaturation = std::log(4.0);

// Blend from white towards `full` by t in [0, 1], rounded to the nearest channel value.
inline Rgb white_towards(const Rgb& full, double t) {
  const auto channel = [t](std::uint8_t target) {
    return static_cast<std::uint8_t>(std::lround(255.0 + t * (target - 255.0)));
  };
  return {channel(full.red), channel(full.green), channel(full.blue)};
}

// sigma1/sigma2 >= 1: white at 1, red from the saturation value on (log scale in between);
// infinite (a zero-area triangle) is full red.
inline Rgb conformal_color(double ratio) {
  if (std::isnan(ratio)) return kUndefinedFill;
  const double t =
      std::clamp(std::log(std::max(ratio, 1.0)) / std::log(kConformalSaturation), 0.0, 1.0);
  return white_towards(Rgb{220, 20, 20}, t);
}

// log(uv area / 3D area): blue where shrunk, white where kept, red where enlarged.
inline Rgb area_color(double log_ratio) {
  if (std::isnan(log_ratio)) return kUndefinedFill;
  const double t = std::clamp(log_ratio / kAreaSaturation, -1.0, 1.0);
  return t >= 0.0 ? white_towards(Rgb{220, 20, 20}, t) : white_towards(Rgb{30, 60, 220}, -t);
}

// A colour bar: position 0 (left end) to 1 (right end) along it, the colour there, and labelled
// ticks. The colours are linear in RGB between the stops (exactly how the colourings above blend),
// so an SVG gradient through the stops shows what the triangles show.
struct ColorBarTick {
  double position = 0.0;
  std::string label;
};

struct ColorBar {
  std::string caption;
  std::vector<ColorBarTick> ticks;
  std::vector<std::pair<double, Rgb>> stops;
  Rgb (*color_at)(double position) = nullptr;
};

// sigma1/sigma2 from 1 to the saturation on a log scale: position p stands for 4^p.
inline ColorBar conformal_color_bar() {
  ColorBar bar;
  bar.caption = "conformal distortion σ1/σ2 (log scale)";
  const double log_saturation = std::log(kConformalSaturation);
  for (const auto& [value, label] : std::vector<std::pair<double, const char*>>{
           {1.0, "1"}, {1.5, "1.5"}, {2.0, "2"}, {3.0, "3"}, {4.0, "≥4"}}) {
    bar.ticks.push_back({std::log(value) / log_saturation, label});
  }
  bar.stops = {{0.0, conformal_color(1.0)}, {1.0, conformal_color(kConformalSaturation)}};
  bar.color_at = [](double position) {
    return conformal_color(std::exp(position * std::log(kConformalSaturation)));
  };
  return bar;
}

// The area factor (normalized UV area / 3D area) from 1/4 to 4 on a log scale: position p stands
// for a log ratio of (2p - 1) log 4.
inline ColorBar area_color_bar() {
  ColorBar bar;
  bar.caption = "area factor: normalized UV area / 3D area (log scale)";
  bar.ticks = {{0.0, "≤1/4"}, {0.25, "1/2"}, {0.5, "1"}, {0.75, "2"}, {1.0, "≥4"}};
  bar.stops = {{0.0, area_color(-kAreaSaturation)}, {0.5, area_color(0.0)},
               {1.0, area_color(kAreaSaturation)}};
  bar.color_at = [](double position) {
    return area_color((2.0 * position - 1.0) * kAreaSaturation);
  };
  return bar;
}

// "#rrggbb" for SVG.
inline std::string hex_color(const Rgb& color) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string text = "#";
  for (const std::uint8_t channel : {color.red, color.green, color.blue}) {
    text += kDigits[channel >> 4];
    text += kDigits[channel & 15];
  }
  return text;
}

}  // namespace harmonia::detail
