// The comparison plot of thesis figure 6.4, made readable: per layout the sorted per-triangle angle
// distortion (left panel) and log area ratio (right panel) against the fraction of triangles. The
// plot is laid out once as a list of filled boxes, curves and texts in pixel coordinates; the SVG
// and PNG renderers draw that list in order, so both formats show the same thing.
#include "harmonia/distortion_plot.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "picture/axis_ticks.h"
#include "picture/color_map.h"
#include "picture/picture_format.h"
#include "picture/pixel_box.h"
#include "picture/raster_image.h"
#include "picture/svg_markup.h"
#include "picture/text_rasterizer.h"

namespace harmonia {
namespace {

using detail::fixed_number;
using detail::PixelBox;
using detail::Rgb;
using detail::TextAnchor;

static_assert(detail::kLayoutColors.size() == kMostPlottedLayouts, "one colour per layout");

constexpr Rgb kPage{255, 255, 255};
constexpr Rgb kGrid{228, 228, 228};
constexpr Rgb kZeroLine{150, 150, 150};
constexpr Rgb kAxis{64, 64, 64};
constexpr Rgb kInk{0, 0, 0};

struct FilledBox {
  PixelBox box;
  Rgb color;
};

struct Curve {
  std::vector<Eigen::Vector2d> points;  // Pixels.
  Rgb color;
  int panel = 0;  // Clipped to that panel's plot box.
};

struct Text {
  std::string text;
  double x = 0.0, y = 0.0;  // Pen start (or middle / end, by anchor) on the baseline.
  double size = 0.0;
  TextAnchor anchor = TextAnchor::start;
  bool upwards = false;  // Turned a quarter counter-clockwise about (x, y).
};

// Everything drawn, in drawing order: boxes under the curves, the curves, boxes over them, texts.
struct PlotContent {
  int width = 0, height = 0;
  std::vector<PixelBox> plot_boxes;  // One per panel.
  std::vector<FilledBox> under;
  std::vector<Curve> curves;
  double curve_width = 0.0;
  std::vector<FilledBox> over;
  std::vector<Text> texts;
};

void validate(const std::vector<LayoutDistortion>& layouts, const DistortionPlotOptions& options) {
  const auto refuse = [](const std::string& problem) {
    throw Error(Status::invalid_input, "write_distortion_plot: " + problem);
  };
  if (layouts.empty()) refuse("no layouts to plot");
  if (static_cast<int>(layouts.size()) > kMostPlottedLayouts) {
    refuse(std::to_string(layouts.size()) + " layouts, but a plot tells at most " +
           std::to_string(kMostPlottedLayouts) + " apart (one colour each)");
  }
  for (std::size_t i = 0; i < layouts.size(); ++i) {
    if (layouts[i].label.empty()) refuse("layout " + std::to_string(i) + " has no label");
  }
  if (options.width_pixels < 320 || options.width_pixels > 16384) {
    refuse("width_pixels " + std::to_string(options.width_pixels) + " is outside [320, 16384]");
  }
  if (options.height_pixels < 240 || options.height_pixels > 16384) {
    refuse("height_pixels " + std::to_string(options.height_pixels) + " is outside [240, 16384]");
  }
}

// The values a curve shows, ascending: NaN left out, infinities kept (drawn at the edge).
std::vector<double> sorted_values(const Eigen::VectorXd& values) {
  std::vector<double> sorted;
  sorted.reserve(static_cast<std::size_t>(values.size()));
  for (const double value : values) {
    if (!std::isnan(value)) sorted.push_back(value);
  }
  std::sort(sorted.begin(), sorted.end());
  return sorted;
}

// The sorted values as a step curve over [0, 1] in plot coordinates (x: fraction, y: value), one
// step per value; beyond two samples per pixel column the steps are sampled, which keeps every
// value a column shows, the smallest and the largest among them.
std::vector<Eigen::Vector2d> step_curve(const std::vector<double>& sorted, double box_width) {
  std::vector<Eigen::Vector2d> points;
  const std::size_t count = sorted.size();
  if (count == 0) return points;
  const std::size_t most_samples = 2 * static_cast<std::size_t>(std::ceil(box_width)) + 2;
  const double n = static_cast<double>(count);
  if (2 * count <= most_samples) {
    for (std::size_t k = 0; k < count; ++k) {
      points.emplace_back(k / n, sorted[k]);
      points.emplace_back((k + 1) / n, sorted[k]);
    }
    return points;
  }
  for (std::size_t j = 0; j < most_samples; ++j) {
    const double x = static_cast<double>(j) / static_cast<double>(most_samples - 1);
    const std::size_t k = std::min(count - 1, static_cast<std::size_t>(std::floor(x * n)));
    points.emplace_back(x, sorted[k]);
  }
  return points;
}


struct PanelSpec {
  std::string heading;
  std::string y_label;
  detail::AxisTicks y_ticks;
  std::vector<std::vector<double>> sorted;  // Per layout.
  bool zero_line = false;
};

// The largest finite |value| over all layouts' sorted values (0 if there is none).
double largest_magnitude(const std::vector<std::vector<double>>& sorted) {
  double largest = 0.0;
  for (const std::vector<double>& values : sorted) {
    for (const double value : values) {
      if (std::isfinite(value)) largest = std::max(largest, std::abs(value));
    }
  }
  return largest;
}

std::vector<PanelSpec> panel_specs(const std::vector<LayoutDistortion>& layouts) {
  PanelSpec angle;
  angle.heading = "angle distortion per triangle";
  angle.y_label = "|UV angle − 3D angle| / 3D angle, mean of the 3 corners";
  PanelSpec area;
  area.heading = "area distortion per triangle";
  area.y_label = "log(normalized UV area / 3D area)";
  area.zero_line = true;
  for (const LayoutDistortion& layout : layouts) {
    angle.sorted.push_back(sorted_values(layout.face_angle_distortion));
    area.sorted.push_back(sorted_values(layout.face_area_log_ratio));
  }
  const double angle_top = largest_magnitude(angle.sorted);
  angle.y_ticks = detail::axis_ticks(0.0, angle_top > 0.0 ? angle_top : 1.0, 5);
  const double area_reach = largest_magnitude(area.sorted);
  const double reach = area_reach > 0.0 ? area_reach : 1.0;
  area.y_ticks = detail::axis_ticks(-reach, reach, 6);
  return {angle, area};
}

// Sizes in pixels that follow the plot's size; fonts in pixels per em.
struct PlotSizes {
  double label = 0.0;
  double title = 0.0;
  double heading = 0.0;
  double margin = 0.0;
  double line = 0.0;  // Grid, ticks, frame.
  double tick_length = 0.0;
  double curve = 0.0;  // Curve width.
};

PlotSizes plot_sizes(double width, double height) {
  const double base = std::min(width / 2.0, height);  // Each panel is about base x base.
  PlotSizes sizes;
  sizes.label = std::max(11.0, base / 55.0);
  sizes.title = 1.3 * sizes.label;
  sizes.heading = 1.1 * sizes.label;
  sizes.margin = 0.025 * base;
  sizes.line = std::max(1.0, sizes.label / 14.0);
  sizes.tick_length = 0.35 * sizes.label;
  sizes.curve = std::max(1.5, base / 400.0);
  return sizes;
}

// The legend along the bottom: per layout a line sample in its colour and its label, left to
// right, wrapped into rows. Returns the legend's top.
double add_legend(PlotContent& plot, const std::vector<LayoutDistortion>& layouts,
                  const PlotSizes& sizes, const detail::TextRasterizer& font) {
  const double label = sizes.label, margin = sizes.margin, width = plot.width;
  const double sample_length = 2.2 * label, row_height = 1.5 * label;
  struct Entry {
    double x;
    int row;
    double size;
  };
  std::vector<Entry> entries;
  double cursor = margin;
  int row = 0;
  for (const LayoutDistortion& layout : layouts) {
    const double size =
        detail::fitted_size(font, layout.label, label, width - 2.0 * margin - sample_length - 0.5 * label);
    const double entry_width = sample_length + 0.5 * label + font.width(layout.label, size);
    if (cursor > margin && cursor + entry_width > width - margin) {
      cursor = margin;
      ++row;
    }
    entries.push_back({cursor, row, size});
    cursor += entry_width + 1.6 * label;
  }
  const double legend_top = plot.height - margin - (row + 1) * row_height;
  for (std::size_t i = 0; i < layouts.size(); ++i) {
    const double baseline = legend_top + entries[i].row * row_height + 1.0 * label;
    const double middle = baseline - 0.3 * label;  // Of lowercase letters.
    plot.over.push_back({{entries[i].x, middle - 0.5 * plot.curve_width,
                          entries[i].x + sample_length, middle + 0.5 * plot.curve_width},
                         detail::kLayoutColors[i]});
    plot.texts.push_back(
        {layouts[i].label, entries[i].x + sample_length + 0.5 * label, baseline, entries[i].size});
  }
  return legend_top;
}

// One panel inside `area`: heading, plot box with grid, ticks and their labels, axis labels, and
// one curve per layout (panel number `index`).
void add_panel(PlotContent& plot, const PanelSpec& panel, int index, const PixelBox& area,
               const PlotSizes& sizes, const detail::TextRasterizer& font) {
  const double label = sizes.label, line = sizes.line, tick_length = sizes.tick_length;
  double y_label_width = 0.0;
  for (const std::string& tick_label : panel.y_ticks.labels)
    y_label_width = std::max(y_label_width, font.width(tick_label, label));
  PixelBox box;
  box.left = area.left + 1.5 * label + y_label_width + 0.3 * label + tick_length;
  box.right = area.right - 0.6 * label;
  const double heading_baseline = area.top + 0.95 * sizes.heading;
  box.top = heading_baseline + 0.8 * label;
  box.bottom = std::max(box.top + 1.0, area.bottom - tick_length - 2.7 * label);
  plot.plot_boxes.push_back(box);
  plot.texts.push_back({panel.heading, 0.5 * (box.left + box.right), heading_baseline,
                        detail::fitted_size(font, panel.heading, sizes.heading, area.width()),
                        TextAnchor::middle});

  const auto x_pixel = [&](double fraction) { return box.left + fraction * box.width(); };
  const auto y_pixel = [&](double value) {
    const detail::AxisTicks& ticks = panel.y_ticks;
    const double clamped = std::clamp(value, ticks.low, ticks.high);
    return box.bottom - (clamped - ticks.low) / (ticks.high - ticks.low) * box.height();
  };

  plot.under.push_back({box, kPage});
  for (std::size_t t = 0; t < panel.y_ticks.values.size(); ++t) {
    const double y = y_pixel(panel.y_ticks.values[t]);
    const bool zero = panel.zero_line && panel.y_ticks.values[t] == 0.0;
    plot.under.push_back(
        {{box.left, y - 0.5 * line, box.right, y + 0.5 * line}, zero ? kZeroLine : kGrid});
    plot.over.push_back(
        {{box.left - tick_length, y - 0.5 * line, box.left, y + 0.5 * line}, kAxis});
    plot.texts.push_back({panel.y_ticks.labels[t], box.left - tick_length - 0.3 * label,
                          y + 0.36 * label, label, TextAnchor::end});
  }
  const detail::AxisTicks x_ticks = detail::axis_ticks(0.0, 1.0, 5);
  for (std::size_t t = 0; t < x_ticks.values.size(); ++t) {
    const double x = x_pixel(x_ticks.values[t]);
    plot.under.push_back({{x - 0.5 * line, box.top, x + 0.5 * line, box.bottom}, kGrid});
    plot.over.push_back(
        {{x - 0.5 * line, box.bottom, x + 0.5 * line, box.bottom + tick_length}, kAxis});
    plot.texts.push_back(
        {x_ticks.labels[t], x, box.bottom + tick_length + 1.0 * label, label, TextAnchor::middle});
  }
  // The frame, drawn over the curves' ends.
  const double half = 0.5 * line;
  plot.over.push_back({{box.left - half, box.top - half, box.right + half, box.top + half}, kAxis});
  plot.over.push_back(
      {{box.left - half, box.bottom - half, box.right + half, box.bottom + half}, kAxis});
  plot.over.push_back({{box.left - half, box.top, box.left + half, box.bottom}, kAxis});
  plot.over.push_back({{box.right - half, box.top, box.right + half, box.bottom}, kAxis});

  const std::string x_label = "fraction of triangles (sorted by value)";
  plot.texts.push_back({x_label, 0.5 * (box.left + box.right),
                        box.bottom + tick_length + 2.4 * label,
                        detail::fitted_size(font, x_label, label, box.width()), TextAnchor::middle});
  plot.texts.push_back({panel.y_label, area.left + 0.95 * label, 0.5 * (box.top + box.bottom),
                        detail::fitted_size(font, panel.y_label, label, box.height()), TextAnchor::middle,
                        true});

  for (std::size_t i = 0; i < panel.sorted.size(); ++i) {
    Curve curve;
    curve.color = detail::kLayoutColors[i];
    curve.panel = index;
    for (const Eigen::Vector2d& point : step_curve(panel.sorted[i], box.width()))
      curve.points.emplace_back(x_pixel(point.x()), y_pixel(point.y()));
    plot.curves.push_back(std::move(curve));
  }
}

PlotContent lay_out_plot(const std::vector<LayoutDistortion>& layouts,
                         const DistortionPlotOptions& options, const detail::TextRasterizer& font) {
  PlotContent plot;
  plot.width = options.width_pixels;
  plot.height = options.height_pixels;
  const PlotSizes sizes = plot_sizes(plot.width, plot.height);
  plot.curve_width = sizes.curve;

  const std::string title =
      options.title.empty()
          ? "per-triangle distortion of " + std::to_string(layouts.size()) + " layouts, sorted"
          : options.title;
  plot.texts.push_back({title, sizes.margin, sizes.margin + 0.95 * sizes.title,
                        detail::fitted_size(font, title, sizes.title, plot.width - 2.0 * sizes.margin)});
  const double legend_top = add_legend(plot, layouts, sizes, font);

  // The two panels side by side between the title and the legend.
  const double top = sizes.margin + 1.5 * sizes.title, bottom = legend_top - 0.6 * sizes.label;
  const double gap = 2.0 * sizes.label;
  const double panel_width = (plot.width - 2.0 * sizes.margin - gap) / 2.0;
  const std::vector<PanelSpec> panels = panel_specs(layouts);
  for (std::size_t p = 0; p < panels.size(); ++p) {
    const double left = sizes.margin + static_cast<double>(p) * (panel_width + gap);
    add_panel(plot, panels[p], static_cast<int>(p), {left, top, left + panel_width, bottom}, sizes,
              font);
  }
  return plot;
}

// ---------------------------------------------------------------------------------------------
// SVG

std::string svg_box(const FilledBox& filled) {
  return "<rect x=\"" + fixed_number(filled.box.left, 2) + "\" y=\"" +
         fixed_number(filled.box.top, 2) + "\" width=\"" + fixed_number(filled.box.width(), 2) +
         "\" height=\"" + fixed_number(filled.box.height(), 2) + "\" fill=\"" +
         detail::hex_color(filled.color) + "\"/>\n";
}

std::string render_svg(const PlotContent& plot) {
  const std::string width = std::to_string(plot.width), height = std::to_string(plot.height);
  std::string svg = "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
  svg += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + width + "\" height=\"" + height +
         "\" viewBox=\"0 0 " + width + " " + height + "\">\n";
  svg += "<rect width=\"" + width + "\" height=\"" + height + "\" fill=\"" +
         detail::hex_color(kPage) + "\"/>\n<defs>";
  for (std::size_t p = 0; p < plot.plot_boxes.size(); ++p) {
    const PixelBox& box = plot.plot_boxes[p];
    svg += "<clipPath id=\"panel-" + std::to_string(p) + "\"><rect x=\"" +
           fixed_number(box.left, 2) + "\" y=\"" + fixed_number(box.top, 2) + "\" width=\"" +
           fixed_number(box.width(), 2) + "\" height=\"" + fixed_number(box.height(), 2) +
           "\"/></clipPath>";
  }
  svg += "</defs>\n";
  for (const FilledBox& filled : plot.under) svg += svg_box(filled);
  for (const Curve& curve : plot.curves) {
    if (curve.points.empty()) continue;
    svg += "<polyline clip-path=\"url(#panel-" + std::to_string(curve.panel) +
           ")\" fill=\"none\" stroke=\"" + detail::hex_color(curve.color) + "\" stroke-width=\"" +
           fixed_number(plot.curve_width, 2) +
           "\" stroke-linejoin=\"round\" stroke-linecap=\"round\" points=\"";
    for (std::size_t k = 0; k < curve.points.size(); ++k) {
      if (k > 0) svg += ' ';
      svg += fixed_number(curve.points[k].x(), 2) + "," + fixed_number(curve.points[k].y(), 2);
    }
    svg += "\"/>\n";
  }
  for (const FilledBox& filled : plot.over) svg += svg_box(filled);
  for (const Text& text : plot.texts) {
    svg += detail::svg_text(text.x, text.y, text.size, text.anchor, kInk, text.text,
                            text.upwards ? -90.0 : 0.0);
  }
  return svg + "</svg>\n";
}

// ---------------------------------------------------------------------------------------------
// PNG

std::string render_png(const PlotContent& plot, const detail::TextRasterizer& font) {
  detail::RgbImage image(plot.width, plot.height, kPage);
  for (const FilledBox& filled : plot.under) image.fill_box(filled.box, filled.color);
  for (const Curve& curve : plot.curves) {
    image.stroke_polyline(curve.points, plot.curve_width, curve.color,
                          plot.plot_boxes[static_cast<std::size_t>(curve.panel)]);
  }
  for (const FilledBox& filled : plot.over) image.fill_box(filled.box, filled.color);
  for (const Text& text : plot.texts) {
    const double advance = font.width(text.text, text.size);
    const double shift = text.anchor == TextAnchor::middle ? 0.5 * advance
                         : text.anchor == TextAnchor::end  ? advance
                                                           : 0.0;
    if (text.upwards) {
      // Reading upwards from (x, y + shift): the pen runs towards smaller y.
      image.draw_text(font.rasterize(text.text, text.size).turned_counterclockwise(), text.x,
                      text.y + shift, kInk);
    } else {
      image.draw_text(font.rasterize(text.text, text.size), text.x - shift, text.y, kInk);
    }
  }
  return image.encode_png();
}

}  // namespace

void write_distortion_plot(const std::filesystem::path& path,
                           const std::vector<LayoutDistortion>& layouts,
                           const DistortionPlotOptions& options) {
  const detail::PictureFormat format = detail::picture_format(path, "write_distortion_plot");
  validate(layouts, options);
  const detail::TextRasterizer font;
  const PlotContent plot = lay_out_plot(layouts, options, font);
  detail::write_file_atomically(
      path, format == detail::PictureFormat::svg ? render_svg(plot) : render_png(plot, font));
}

}  // namespace harmonia
