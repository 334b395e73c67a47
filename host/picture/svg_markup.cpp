// SVG markup shared by the pictures and the plots.
#include "picture/svg_markup.h"

#include <array>
#include <charconv>

namespace harmonia::detail {

std::string fixed_number(double value, int decimals) {
  std::array<char, 64> buffer{};
  const auto result = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value,
                                    std::chars_format::fixed, decimals);
  std::string text(buffer.data(), result.ptr);
  if (text.front() == '-' && text.find_first_not_of("-0.") == std::string::npos) text.erase(0, 1);
  return text;
}

std::string xml_escape(std::string_view text) {
  std::string escaped;
  escaped.reserve(text.size());
  for (const char letter : text) {
    switch (letter) {
      case '&':
        escaped += "&amp;";
        break;
      case '<':
        escaped += "&lt;";
        break;
      case '>':
        escaped += "&gt;";
        break;
      case '"':
        escaped += "&quot;";
        break;
      case '\'':
        escaped += "&apos;";
        break;
      default:
        escaped += letter;
    }
  }
  return escaped;
}

std::string svg_text(double x, double y, double font_size, TextAnchor anchor, const Rgb& color,
                     std::string_view text, double rotate_degrees) {
  const std::string at_x = fixed_number(x, 1), at_y = fixed_number(y, 1);
  std::string element = "<text x=\"" + at_x + "\" y=\"" + at_y +
                        "\" font-family=\"DejaVu Sans, Verdana, sans-serif\" font-size=\"" +
                        fixed_number(font_size, 1) + "\" fill=\"" + hex_color(color) + "\"";
  if (anchor == TextAnchor::middle) element += " text-anchor=\"middle\"";
  if (anchor == TextAnchor::end) element += " text-anchor=\"end\"";
  if (rotate_degrees != 0.0) {
    element +=
        " transform=\"rotate(" + fixed_number(rotate_degrees, 1) + " " + at_x + " " + at_y + ")\"";
  }
  return element + ">" + xml_escape(text) + "</text>\n";
}

}  // namespace harmonia::detail
