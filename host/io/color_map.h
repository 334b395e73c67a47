#pragma once
// Internal: the colours of a distortion picture. Undistorted is white, so that in a good map every
// coloured patch is a problem worth seeing; the background is a light grey that sets it off.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>

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
