// Pictures of spherical maps: two opposite views of the unit sphere, each a small software
// rasterizer (orthographic projection, a depth buffer that also keeps which face is seen, flat
// Lambert shading), with the date line and the poles drawn over the visible surface, and the
// colour bar and legend below. Everything is drawn in a fixed order with integer blending
// (io/raster_image.h), so the same map gives the same bytes.
#include "harmonia/sphere_picture.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "io/color_bar_drawing.h"
#include "io/color_map.h"
#include "io/pixel_box.h"
#include "io/raster_image.h"
#include "io/svg_markup.h"
#include "io/text_rasterizer.h"

namespace harmonia {
namespace {

using detail::PixelBox;
using detail::Rgb;

constexpr Rgb kInk{0, 0, 0};
constexpr Rgb kWhite{255, 255, 255};
// The date line: a yellow core, a colour the area map never uses, with a dark edge that keeps it
// apart from white and light red triangles alike.
constexpr Rgb kDateLineCore{255, 204, 0};
constexpr Rgb kDateLineEdge{40, 40, 40};

// How far the first view looks from the north pole towards the date line: both poles and the
// whole date line then lie well inside one view or the other, instead of on their rims.
constexpr double kViewTilt = std::numbers::pi / 6.0;
// Triangles marked as turned over are pulled this far (unit sphere) towards the viewer, so that
// the layers of a fold, at nearly the same depth, do not hide them.
constexpr double kMarkedDepthBias = 0.01;
// Flat shading: ambient plus diffuse share of a face's colour. Enough diffuse light to show the
// sphere's shape, enough ambient light to keep the colours readable out to the rim.
constexpr double kAmbient = 0.6;
constexpr double kDiffuse = 0.4;
// Below this mean visible triangle size (pixels) edges would cover the colours; they are left out.
constexpr double kEdgeMinimumPixels = 40.0;
// Edges are blended in lightly (of 255), so that they outline triangles without darkening them.
constexpr int kEdgeCoverage = 72;

// ---------------------------------------------------------------------------------------------
// The map as drawn

struct SphereContent {
  Eigen::MatrixX3d points;     // Unit length; NaN rows where a point has no direction.
  std::vector<Rgb> fill;       // Per face: the area colour, or kFlippedFill when marked.
  std::vector<char> marked;    // Per face: turned over or degenerate on the sphere.
  std::vector<char> drawable;  // Per face: all three points finite.
  int marked_count = 0;
  std::string title;
};

void validate(const Mesh& mesh, const Eigen::MatrixX3d& sphere_points,
              const SpherePictureOptions& options) {
  const auto refuse = [](const std::string& problem) {
    throw Error(Status::invalid_input, "write_sphere_picture: " + problem);
  };
  if (options.width < 320 || options.width > 16384)
    refuse("width " + std::to_string(options.width) + " is outside [320, 16384]");
  if (options.height < 240 || options.height > 16384)
    refuse("height " + std::to_string(options.height) + " is outside [240, 16384]");
  const Eigen::Index vertices = mesh.vertices.rows();
  if (sphere_points.rows() != vertices)
    refuse(std::to_string(sphere_points.rows()) + " sphere points for " + std::to_string(vertices) +
           " vertices");
  const auto is_vertex = [vertices](Eigen::Index v) { return v >= 0 && v < vertices; };
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f)
    for (int corner = 0; corner < 3; ++corner)
      if (!is_vertex(mesh.faces(f, corner)))
        refuse("face " + std::to_string(f) + " names vertex " +
               std::to_string(mesh.faces(f, corner)) + ", which does not exist");
  for (const auto& [pole, name] :
       {std::pair{options.north_pole, "north_pole"}, std::pair{options.south_pole, "south_pole"}})
    if (pole != -1 && !is_vertex(pole))
      refuse(std::string(name) + " " + std::to_string(pole) + " is not a vertex");
  for (const int v : options.date_line)
    if (!is_vertex(v)) refuse("date line vertex " + std::to_string(v) + " is not a vertex");
}

SphereContent sphere_content(const Mesh& mesh, const Eigen::MatrixX3d& sphere_points,
                             const SpherePictureOptions& options) {
  const SphericalMetrics metrics = spherical_metrics(mesh, sphere_points);
  SphereContent content;
  content.title = options.title.empty() ? sphere_picture_headline(metrics) : options.title;
  content.points = sphere_points;
  for (Eigen::Index v = 0; v < content.points.rows(); ++v) {
    const double radius = content.points.row(v).norm();
    if (radius > 0.0 && std::isfinite(radius))
      content.points.row(v) /= radius;
    else
      content.points.row(v).setConstant(std::numeric_limits<double>::quiet_NaN());
  }
  const auto faces = static_cast<std::size_t>(mesh.faces.rows());
  content.fill.resize(faces);
  content.marked.resize(faces);
  content.drawable.resize(faces);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const auto i = static_cast<std::size_t>(f);
    content.drawable[i] = content.points.row(mesh.faces(f, 0)).allFinite() &&
                          content.points.row(mesh.faces(f, 1)).allFinite() &&
                          content.points.row(mesh.faces(f, 2)).allFinite();
    content.marked[i] = metrics.face_orientation[f] <= 0;
    content.marked_count += content.marked[i];
    content.fill[i] = content.marked[i] ? detail::kFlippedFill
                                        : detail::area_color(metrics.face_area_log_ratio[f]);
  }
  return content;
}

// ---------------------------------------------------------------------------------------------
// Where things go

struct Sizes {
  double margin = 0.0;
  double label = 0.0;  // Font sizes, pixels per em.
  double title = 0.0;
  double heading = 0.0;
  double line = 0.0;  // Outlines and ticks.
};

Sizes picture_sizes(int width, int height) {
  const double base = std::min(width / 2.0, static_cast<double>(height));  // One view's square.
  Sizes sizes;
  sizes.margin = 0.025 * base;
  sizes.label = std::max(11.0, base / 50.0);
  sizes.title = 1.3 * sizes.label;
  sizes.heading = 1.1 * sizes.label;
  sizes.line = std::max(1.0, sizes.label / 12.0);
  return sizes;
}

// One view: orthographic, the viewer far out along `toward`, `up` pointing up the picture.
struct View {
  Eigen::Vector3d toward, up, right;
  Eigen::Vector2d centre;  // Pixels.
  double radius = 0.0;     // Pixels per unit.
  PixelBox panel;          // Everything of this view is drawn inside.
  std::string heading;
  double heading_baseline = 0.0;

  [[nodiscard]] Eigen::Vector2d pixel(const Eigen::Vector3d& point) const {
    return centre + radius * Eigen::Vector2d(point.dot(right), -point.dot(up));
  }
  [[nodiscard]] double depth(const Eigen::Vector3d& point) const { return point.dot(toward); }
};

// Any unit vector perpendicular to `axis` (unit), chosen from the coordinate axis least along it.
Eigen::Vector3d perpendicular(const Eigen::Vector3d& axis) {
  Eigen::Index least = 0;
  axis.cwiseAbs().minCoeff(&least);
  const Eigen::Vector3d e = Eigen::Vector3d::Unit(least);
  return (e - e.dot(axis) * axis).normalized();
}

std::optional<Eigen::Vector3d> pole_point(const SphereContent& content, int pole) {
  if (pole < 0 || !content.points.row(pole).allFinite()) return std::nullopt;
  return Eigen::Vector3d(content.points.row(pole));
}

// The two views' directions: from kViewTilt beside the north pole towards the date line's side,
// and from the opposite side; along +z and -z when there are no poles.
std::array<View, 2> view_directions(const SphereContent& content,
                                    const SpherePictureOptions& options) {
  const std::optional<Eigen::Vector3d> north = pole_point(content, options.north_pole);
  const std::optional<Eigen::Vector3d> south = pole_point(content, options.south_pole);
  std::array<View, 2> views;
  if (!north && !south) {
    views[0].toward = Eigen::Vector3d::UnitZ();
    views[0].up = Eigen::Vector3d::UnitY();
    views[0].heading = "seen from +z";
    views[1].heading = "seen from −z";
  } else {
    Eigen::Vector3d axis = north && south ? Eigen::Vector3d(*north - *south)
                           : north        ? *north
                                          : Eigen::Vector3d(-*south);
    if (axis.norm() < 1e-9) axis = north ? *north : Eigen::Vector3d(-*south);  // Collapsed map.
    axis.normalize();
    Eigen::Vector3d side = Eigen::Vector3d::Zero();
    for (const int v : options.date_line)
      if (content.points.row(v).allFinite()) side += content.points.row(v).transpose();
    side -= side.dot(axis) * axis;
    side = side.norm() > 1e-6 ? side.normalized() : perpendicular(axis);
    views[0].toward = std::cos(kViewTilt) * axis + std::sin(kViewTilt) * side;
    views[0].up = (axis - axis.dot(views[0].toward) * views[0].toward).normalized();
    views[0].heading = "north pole side, facing the date line";
    views[1].heading = "south pole side, facing away from it";
  }
  views[1].toward = -views[0].toward;
  views[1].up = views[0].up;
  for (View& view : views) view.right = view.up.cross(view.toward);
  return views;
}

// The colour bar, its caption and tick labels, and the legend entries right of it.
struct Legend {
  detail::ColorBar bar;
  PixelBox bar_box;
  double caption_baseline = 0.0;
  double caption_size = 0.0;
  double tick_length = 0.0;
  double tick_label_baseline = 0.0;
  double tick_label_size = 0.0;
  double entries_left = 0.0;  // The marked triangles' swatch, the date line, the poles.
  double entry_size = 0.0;
  std::vector<std::string> entry_labels;  // The marked triangles', then those of what is drawn.
};

struct Layout {
  int width = 0, height = 0;
  Sizes sizes;
  std::string title;
  double title_size = 0.0;
  double title_baseline = 0.0;
  std::array<View, 2> views;
  Legend legend;
};


// The legend's entries in a row: swatch, gap, label, space; their total width at font size `size`.
constexpr double kSwatchInLabels = 1.1;
constexpr double kEntryGapInLabels = 0.5;
constexpr double kEntrySpaceInLabels = 1.5;
const std::string kDateLineLabel = "date line";
const std::string kPolesLabel = "poles";

double legend_entries_width(const detail::TextRasterizer& font, const Legend& legend, double size) {
  double width = 0.0;
  for (const std::string& label : legend.entry_labels)
    width += (kSwatchInLabels + kEntryGapInLabels + kEntrySpaceInLabels) * size +
             font.width(label, size);
  return width;
}

Legend lay_out_legend(const Layout& layout, const SphereContent& content,
                      const SpherePictureOptions& options, const detail::TextRasterizer& font) {
  const Sizes& sizes = layout.sizes;
  const double label = sizes.label;
  Legend legend;
  legend.bar = detail::area_color_bar();
  legend.bar.caption = "area factor: normalized sphere area / 3D area (log scale)";
  const double bar_top = layout.height - sizes.margin - (1.1 + 0.35 + 1.25) * label;
  const double bar_left = sizes.margin + 1.2 * label;
  legend.bar_box = {bar_left, bar_top, bar_left + 0.42 * (layout.width - 2.0 * sizes.margin),
                    bar_top + 1.1 * label};
  legend.caption_baseline = bar_top - 0.4 * label;
  legend.caption_size = detail::fitted_size(font, legend.bar.caption, label,
                                    layout.width - sizes.margin - legend.bar_box.left);
  legend.tick_length = 0.35 * label;
  legend.tick_label_baseline = legend.bar_box.bottom + legend.tick_length + 0.95 * label;
  // Tick labels no wider than 0.8 of the closest ticks' distance, so that neighbours stay apart.
  double closest = legend.bar_box.width(), widest = 0.0;
  const std::vector<detail::ColorBarTick>& ticks = legend.bar.ticks;
  for (std::size_t i = 0; i < ticks.size(); ++i) {
    widest = std::max(widest, font.width(ticks[i].label, label));
    if (i > 0)
      closest =
          std::min(closest, (ticks[i].position - ticks[i - 1].position) * legend.bar_box.width());
  }
  legend.tick_label_size = widest > 0.8 * closest ? label * 0.8 * closest / widest : label;

  legend.entry_labels = {"turned over or degenerate, ringed (" +
                         std::to_string(content.marked_count) + ")"};
  if (options.date_line.size() >= 2) legend.entry_labels.push_back(kDateLineLabel);
  if (options.north_pole >= 0 || options.south_pole >= 0)
    legend.entry_labels.push_back(kPolesLabel);
  legend.entries_left = legend.bar_box.right + 2.5 * label;
  const double room = layout.width - sizes.margin - legend.entries_left;
  const double natural = legend_entries_width(font, legend, label);
  legend.entry_size = natural > room && natural > 0.0 ? label * room / natural : label;
  return legend;
}

Layout lay_out(const SphereContent& content, const SpherePictureOptions& options,
               const detail::TextRasterizer& font) {
  Layout layout;
  layout.width = options.width;
  layout.height = options.height;
  layout.sizes = picture_sizes(options.width, options.height);
  const Sizes& sizes = layout.sizes;
  layout.title = content.title;
  layout.title_size =
      detail::fitted_size(font, layout.title, sizes.title, options.width - 2.0 * sizes.margin);
  layout.title_baseline = sizes.margin + 0.95 * sizes.title;
  layout.legend = lay_out_legend(layout, content, options, font);

  // The two views side by side between the title and the legend, each with its heading on top.
  const double heading_baseline = sizes.margin + 1.5 * sizes.title + 0.95 * sizes.heading;
  const double top = heading_baseline + 0.5 * sizes.label;
  const double bottom = layout.legend.caption_baseline - 1.3 * sizes.label;
  const double gap = 2.0 * sizes.label;
  const double panel_width = (options.width - 2.0 * sizes.margin - gap) / 2.0;
  layout.views = view_directions(content, options);
  for (std::size_t i = 0; i < layout.views.size(); ++i) {
    View& view = layout.views[i];
    const double left = sizes.margin + static_cast<double>(i) * (panel_width + gap);
    view.panel = {left, top, left + panel_width, std::max(top + 1.0, bottom)};
    view.centre = {0.5 * (view.panel.left + view.panel.right),
                   0.5 * (view.panel.top + view.panel.bottom)};
    // A little room outside the disk for the rings around marked triangles at its rim.
    view.radius =
        std::max(2.0, 0.5 * std::min(view.panel.width(), view.panel.height()) - 0.6 * sizes.label);
    view.heading_baseline = heading_baseline;
  }
  return layout;
}

// ---------------------------------------------------------------------------------------------
// The rasterizer of one view: per pixel the nearest face's depth and index.

class ViewRaster {
 public:
  ViewRaster(const View& view, int image_width, int image_height) : view_(view) {
    left_ = std::max(0, static_cast<int>(std::floor(view.centre.x() - view.radius)) - 1);
    top_ = std::max(0, static_cast<int>(std::floor(view.centre.y() - view.radius)) - 1);
    const int right =
        std::min(image_width, static_cast<int>(std::ceil(view.centre.x() + view.radius)) + 2);
    const int bottom =
        std::min(image_height, static_cast<int>(std::ceil(view.centre.y() + view.radius)) + 2);
    width_ = std::max(0, right - left_);
    height_ = std::max(0, bottom - top_);
    const auto cells = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
    depth_.assign(cells, -std::numeric_limits<double>::infinity());
    face_.assign(cells, -1);
  }

  // Draws face `f` (corners a, b, c on the sphere) into the buffers: where its chord triangle
  // covers a pixel's centre and lies nearer than what is there. Ties keep the earlier face.
  void rasterize(int f, const std::array<Eigen::Vector3d, 3>& corners, double depth_bias) {
    std::array<Eigen::Vector2d, 3> at;
    std::array<double, 3> depth;
    for (int k = 0; k < 3; ++k) {
      at[k] = view_.pixel(corners[k]);
      depth[k] = view_.depth(corners[k]) + depth_bias;
    }
    double twice_area = edge(at[0], at[1], at[2]);
    if (twice_area == 0.0) return;  // No interior; a marked one is ringed all the same.
    if (twice_area < 0.0) {
      std::swap(at[1], at[2]);
      std::swap(depth[1], depth[2]);
      twice_area = -twice_area;
    }
    // The cells whose pixel centres may lie in the triangle's bounding box.
    const auto [x_low, x_high] = std::minmax({at[0].x(), at[1].x(), at[2].x()});
    const auto [y_low, y_high] = std::minmax({at[0].y(), at[1].y(), at[2].y()});
    const int x_first = std::max(0, static_cast<int>(std::floor(x_low - 0.5)) - left_);
    const int x_last = std::min(width_ - 1, static_cast<int>(std::ceil(x_high)) - left_);
    const int y_first = std::max(0, static_cast<int>(std::floor(y_low - 0.5)) - top_);
    const int y_last = std::min(height_ - 1, static_cast<int>(std::ceil(y_high)) - top_);
    for (int y = y_first; y <= y_last; ++y) {
      for (int x = x_first; x <= x_last; ++x) {
        const Eigen::Vector2d centre(left_ + x + 0.5, top_ + y + 0.5);
        const double w0 = edge(at[1], at[2], centre), w1 = edge(at[2], at[0], centre),
                     w2 = edge(at[0], at[1], centre);
        if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
        const double z = (w0 * depth[0] + w1 * depth[1] + w2 * depth[2]) / twice_area;
        const std::size_t cell = index(x, y);
        if (z > depth_[cell]) {
          depth_[cell] = z;
          face_[cell] = f;
        }
      }
    }
  }

  // Whether a point of the unit sphere is in front of everything drawn at its pixel. The sphere
  // bulges out of its chord triangles, so a point of the front half never hides behind them; the
  // tolerance covers the pull of marked triangles.
  [[nodiscard]] bool visible(const Eigen::Vector3d& point) const {
    const Eigen::Vector2d at = view_.pixel(point);
    const int x = static_cast<int>(std::floor(at.x())) - left_;
    const int y = static_cast<int>(std::floor(at.y())) - top_;
    const double depth = view_.depth(point);
    constexpr double tolerance = kMarkedDepthBias + 1e-3;
    if (x < 0 || y < 0 || x >= width_ || y >= height_ || face_[index(x, y)] < 0)
      return depth >= -tolerance;  // Off the drawn surface: near the rim, seen if in front.
    return depth >= depth_[index(x, y)] - tolerance;
  }

  [[nodiscard]] int left() const { return left_; }
  [[nodiscard]] int top() const { return top_; }
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  // The face seen at buffer cell (x, y), -1 for none (also outside the buffer).
  [[nodiscard]] int face(int x, int y) const {
    return x < 0 || y < 0 || x >= width_ || y >= height_ ? -1 : face_[index(x, y)];
  }

 private:
  static double edge(const Eigen::Vector2d& a, const Eigen::Vector2d& b, const Eigen::Vector2d& p) {
    return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
  }
  [[nodiscard]] std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(x);
  }

  const View& view_;
  int left_ = 0, top_ = 0, width_ = 0, height_ = 0;
  std::vector<double> depth_;
  std::vector<int> face_;
};

std::array<Eigen::Vector3d, 3> face_corners(const Mesh& mesh, const SphereContent& content,
                                            Eigen::Index f) {
  return {Eigen::Vector3d(content.points.row(mesh.faces(f, 0))),
          Eigen::Vector3d(content.points.row(mesh.faces(f, 1))),
          Eigen::Vector3d(content.points.row(mesh.faces(f, 2)))};
}

// A face's colour lit from the front, a little above and left of the viewer (flat Lambert). The
// normal's sign does not matter: a face turned over is drawn in its marker colour anyway.
Rgb shaded(const Rgb& color, const std::array<Eigen::Vector3d, 3>& corners, const View& view) {
  Eigen::Vector3d normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
  if (!(normal.norm() > 0.0)) normal = corners[0] + corners[1] + corners[2];
  const Eigen::Vector3d light = (view.toward + 0.3 * view.up - 0.25 * view.right).normalized();
  const double cosine = normal.norm() > 0.0 ? std::abs(normal.normalized().dot(light)) : 1.0;
  const double factor = kAmbient + kDiffuse * cosine;
  const auto channel = [factor](std::uint8_t value) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(value * factor, 0.0, 255.0)));
  };
  return {channel(color.red), channel(color.green), channel(color.blue)};
}

// ---------------------------------------------------------------------------------------------
// Drawing

// Text with a thin white halo, readable on any colour of the sphere.
void draw_haloed_text(detail::RgbImage& image, const detail::TextCoverage& text, double x,
                      double baseline, double halo) {
  for (int dy = -1; dy <= 1; ++dy)
    for (int dx = -1; dx <= 1; ++dx)
      if (dx != 0 || dy != 0) image.draw_text(text, x + dx * halo, baseline + dy * halo, kWhite);
  image.draw_text(text, x, baseline, kInk);
}

// The box of `points` grown by `reach` on every side, within `clip`: the stroke primitives work
// over their whole clip box, so each stroke gets only the box it needs.
PixelBox around(const std::vector<Eigen::Vector2d>& points, double reach, const PixelBox& clip) {
  PixelBox box{points[0].x(), points[0].y(), points[0].x(), points[0].y()};
  for (const Eigen::Vector2d& at : points) {
    box = {std::min(box.left, at.x()), std::min(box.top, at.y()), std::max(box.right, at.x()),
           std::max(box.bottom, at.y())};
  }
  return {std::max(clip.left, box.left - reach), std::max(clip.top, box.top - reach),
          std::min(clip.right, box.right + reach), std::min(clip.bottom, box.bottom + reach)};
}

// The date line's widths in pixels: its yellow core and the dark edge around it.
struct DateLineWidths {
  double core = 0.0;
  double edge = 0.0;
};

DateLineWidths date_line_widths(const Sizes& sizes) {
  const double core = std::max(2.0, 0.25 * sizes.label);
  return {core, core + 2.0 * std::max(1.0, 0.6 * sizes.line)};
}

// A round dot: a polyline of one point is drawn as a disk.
void draw_dot(detail::RgbImage& image, const Eigen::Vector2d& at, double radius, const Rgb& color,
              const PixelBox& clip) {
  image.stroke_polyline({at}, 2.0 * radius, color, around({at}, radius + 2.0, clip));
}

void draw_ring(detail::RgbImage& image, const Eigen::Vector2d& at, double radius, double width,
               const Rgb& color, const PixelBox& clip) {
  constexpr int kSegments = 32;
  std::vector<Eigen::Vector2d> points;
  for (int k = 0; k <= kSegments; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / kSegments;
    points.emplace_back(at.x() + radius * std::cos(angle), at.y() + radius * std::sin(angle));
  }
  image.stroke_polyline(points, width, color, around({at}, radius + width + 2.0, clip));
}

// The faces seen, shaded, with edges where triangles are large enough to show them and a marker
// outline around marked ones.
void draw_surface(detail::RgbImage& image, const ViewRaster& raster, const View& view,
                  const Mesh& mesh, const SphereContent& content) {
  std::vector<Rgb> color(content.fill.size());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const auto i = static_cast<std::size_t>(f);
    if (content.drawable[i])
      color[i] = content.marked[i] ? content.fill[i]
                                   : shaded(content.fill[i], face_corners(mesh, content, f), view);
  }
  std::size_t covered = 0;
  std::vector<char> seen(content.fill.size(), 0);
  for (int y = 0; y < raster.height(); ++y) {
    for (int x = 0; x < raster.width(); ++x) {
      const int f = raster.face(x, y);
      if (f < 0) continue;
      image.set(raster.left() + x, raster.top() + y, color[static_cast<std::size_t>(f)]);
      ++covered;
      seen[static_cast<std::size_t>(f)] = 1;
    }
  }
  const auto seen_faces = static_cast<std::size_t>(std::count(seen.begin(), seen.end(), 1));
  const bool edges =
      seen_faces > 0 && static_cast<double>(covered) / seen_faces >= kEdgeMinimumPixels;
  for (int y = 0; y < raster.height(); ++y) {
    for (int x = 0; x < raster.width(); ++x) {
      const int f = raster.face(x, y);
      if (f < 0) continue;
      if (content.marked[static_cast<std::size_t>(f)]) {
        const bool border = raster.face(x + 1, y) != f || raster.face(x - 1, y) != f ||
                            raster.face(x, y + 1) != f || raster.face(x, y - 1) != f;
        if (border) image.set(raster.left() + x, raster.top() + y, detail::kFlippedOutline);
      } else if (edges && (raster.face(x + 1, y) != f || raster.face(x, y + 1) != f)) {
        image.blend(raster.left() + x, raster.top() + y, detail::kEdgeColor, kEdgeCoverage);
      }
    }
  }
}

// A ring around every marked triangle on the side facing the viewer, hidden or not: a fold's
// turned-over layer may lie under another, and a degenerate triangle covers no pixel.
void draw_marker_rings(detail::RgbImage& image, const View& view, const Mesh& mesh,
                       const SphereContent& content, const Sizes& sizes) {
  const double radius = std::max(5.0, 0.6 * sizes.label);
  const double width = std::max(1.5, 1.6 * sizes.line);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const auto i = static_cast<std::size_t>(f);
    if (!content.marked[i] || !content.drawable[i]) continue;
    const std::array<Eigen::Vector3d, 3> corners = face_corners(mesh, content, f);
    const Eigen::Vector3d centroid = (corners[0] + corners[1] + corners[2]) / 3.0;
    if (view.depth(centroid) <= 0.0) continue;  // The other view shows it.
    draw_ring(image, view.pixel(centroid), radius, width, detail::kFlippedOutline, view.panel);
  }
}

// The date line's great-circle arcs, sampled a few pixels apart, cut into the runs the depth test
// lets through; all dark edges first, then all yellow cores, so that crossings stay clean.
void draw_date_line(detail::RgbImage& image, const ViewRaster& raster, const View& view,
                    const SphereContent& content, const std::vector<int>& date_line,
                    const Sizes& sizes) {
  std::vector<std::vector<Eigen::Vector2d>> runs(1);
  const auto add_sample = [&](const Eigen::Vector3d& point) {
    if (raster.visible(point)) {
      runs.back().push_back(view.pixel(point));
    } else if (!runs.back().empty()) {
      runs.emplace_back();
    }
  };
  for (std::size_t k = 0; k + 1 < date_line.size(); ++k) {
    const Eigen::Vector3d a = content.points.row(date_line[k]);
    const Eigen::Vector3d b = content.points.row(date_line[k + 1]);
    if (!a.allFinite() || !b.allFinite()) {
      if (!runs.back().empty()) runs.emplace_back();
      continue;
    }
    const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
    const int samples = std::max(1, static_cast<int>(std::ceil(angle * view.radius / 3.0)));
    for (int s = k == 0 ? 0 : 1; s <= samples; ++s) {
      const double t = static_cast<double>(s) / samples;
      // Spherical interpolation; a and b are never antipodal along an edge path, and where they
      // (nearly) coincide the chord's normalized points are as good.
      const Eigen::Vector3d point =
          std::sin(angle) > 1e-9
              ? Eigen::Vector3d((std::sin((1.0 - t) * angle) * a + std::sin(t * angle) * b) /
                                std::sin(angle))
              : Eigen::Vector3d(((1.0 - t) * a + t * b).normalized());
      add_sample(point);
    }
  }
  const DateLineWidths widths = date_line_widths(sizes);
  for (const Rgb& color : {kDateLineEdge, kDateLineCore}) {
    const double width = color == kDateLineEdge ? widths.edge : widths.core;
    for (const std::vector<Eigen::Vector2d>& run : runs)
      if (!run.empty()) image.stroke_polyline(run, width, color, around(run, width, view.panel));
  }
}

// A pole as a black dot in a white ring, labelled beside it.
void draw_pole_marker(detail::RgbImage& image, const Eigen::Vector2d& at, const std::string& name,
                      const Sizes& sizes, const detail::TextRasterizer& font,
                      const PixelBox& clip) {
  const double radius = std::max(3.5, 0.35 * sizes.label);
  draw_dot(image, at, radius + std::max(1.5, sizes.line), kWhite, clip);
  draw_dot(image, at, radius, kInk, clip);
  if (name.empty()) return;
  const double size = 1.1 * sizes.label;
  draw_haloed_text(image, font.rasterize(name, size), at.x() + radius + 0.35 * size,
                   at.y() + 0.36 * size, std::max(1.0, size / 14.0));
}

void draw_poles(detail::RgbImage& image, const ViewRaster& raster, const View& view,
                const SphereContent& content, const SpherePictureOptions& options,
                const Sizes& sizes, const detail::TextRasterizer& font) {
  for (const auto& [pole, name] :
       {std::pair{options.north_pole, "N"}, std::pair{options.south_pole, "S"}}) {
    const std::optional<Eigen::Vector3d> point = pole_point(content, pole);
    if (point && raster.visible(*point))
      draw_pole_marker(image, view.pixel(*point), name, sizes, font, view.panel);
  }
}

// A box outline `width` pixels wide, drawn inside the box.

void draw_color_bar(detail::RgbImage& image, const Legend& legend, const Sizes& sizes,
                    const detail::TextRasterizer& font) {
  detail::ColorBarPlacement placement;
  placement.box = legend.bar_box;
  placement.caption_baseline = legend.caption_baseline;
  placement.caption_size = legend.caption_size;
  placement.tick_length = legend.tick_length;
  placement.tick_label_baseline = legend.tick_label_baseline;
  placement.tick_label_size = legend.tick_label_size;
  placement.line_width = sizes.line;
  detail::draw_color_bar(image, legend.bar, placement, font, kInk);
}

// Right of the bar, centred on it, each symbol and its label: the marked triangles' swatch, then
// a piece of date line and a pole where the views show them.
void draw_legend_entries(detail::RgbImage& image, const Legend& legend, const Sizes& sizes,
                         const detail::TextRasterizer& font) {
  const double size = legend.entry_size;
  const double middle = 0.5 * (legend.bar_box.top + legend.bar_box.bottom);
  const double swatch = kSwatchInLabels * size;
  const PixelBox everywhere{0.0, 0.0, static_cast<double>(image.width()),
                            static_cast<double>(image.height())};
  double x = legend.entries_left;
  for (std::size_t i = 0; i < legend.entry_labels.size(); ++i) {
    const std::string& text = legend.entry_labels[i];
    if (i == 0) {
      const PixelBox marked{x, middle - 0.5 * swatch, x + swatch, middle + 0.5 * swatch};
      image.fill_box(marked, detail::kFlippedFill);
      image.outline_box(marked, 2.0 * sizes.line, detail::kFlippedOutline);
    } else if (text == kDateLineLabel) {
      const DateLineWidths widths = date_line_widths(sizes);
      const std::vector<Eigen::Vector2d> piece{{x + 0.5 * widths.edge, middle},
                                               {x + swatch - 0.5 * widths.edge, middle}};
      const PixelBox clip = around(piece, widths.edge, everywhere);
      image.stroke_polyline(piece, widths.edge, kDateLineEdge, clip);
      image.stroke_polyline(piece, widths.core, kDateLineCore, clip);
    } else {
      draw_pole_marker(image, {x + 0.5 * swatch, middle}, "", sizes, font, everywhere);
    }
    x += swatch + kEntryGapInLabels * size;
    image.draw_text(font.rasterize(text, size), x, middle + 0.36 * size, kInk);
    x += font.width(text, size) + kEntrySpaceInLabels * size;
  }
}

std::string render_png(const Mesh& mesh, const SphereContent& content, const Layout& layout,
                       const SpherePictureOptions& options, const detail::TextRasterizer& font) {
  detail::RgbImage image(layout.width, layout.height, detail::kBackground);
  image.draw_text(font.rasterize(layout.title, layout.title_size), layout.sizes.margin,
                  layout.title_baseline, kInk);
  for (const View& view : layout.views) {
    const double heading_size =
        detail::fitted_size(font, view.heading, layout.sizes.heading, view.panel.width());
    image.draw_text(font.rasterize(view.heading, heading_size),
                    view.centre.x() - 0.5 * font.width(view.heading, heading_size),
                    view.heading_baseline, kInk);
    ViewRaster raster(view, layout.width, layout.height);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
      const auto i = static_cast<std::size_t>(f);
      if (!content.drawable[i]) continue;
      raster.rasterize(static_cast<int>(f), face_corners(mesh, content, f),
                       content.marked[i] ? kMarkedDepthBias : 0.0);
    }
    draw_surface(image, raster, view, mesh, content);
    draw_date_line(image, raster, view, content, options.date_line, layout.sizes);
    draw_marker_rings(image, view, mesh, content, layout.sizes);
    draw_poles(image, raster, view, content, options, layout.sizes, font);
  }
  draw_color_bar(image, layout.legend, layout.sizes, font);
  draw_legend_entries(image, layout.legend, layout.sizes, font);
  return image.encode_png();
}

// Only PNG: the views are rasterized.
void require_png(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  for (char& letter : extension)
    letter = static_cast<char>(std::tolower(static_cast<unsigned char>(letter)));
  if (extension != ".png")
    throw Error(Status::io_error, "write_sphere_picture: unknown picture format '" + extension +
                                      "' of '" + path.string() + "' (use .png)");
}

}  // namespace

std::string sphere_picture_headline(const SphericalMetrics& metrics) {
  std::string headline = std::to_string(metrics.flipped_triangles) + " flipped";
  if (metrics.degenerate_triangles > 0)
    headline += ", " + std::to_string(metrics.degenerate_triangles) + " degenerate";
  return headline + ", area distortion " + detail::fixed_number(metrics.area_distortion_mean, 2);
}

void write_sphere_picture(const std::filesystem::path& png, const Mesh& mesh,
                          const Eigen::MatrixX3d& sphere_points,
                          const SpherePictureOptions& options) {
  require_png(png);  // Before any work.
  validate(mesh, sphere_points, options);
  const SphereContent content = sphere_content(mesh, sphere_points, options);
  const detail::TextRasterizer font;
  const Layout layout = lay_out(content, options, font);
  detail::write_file_atomically(png, render_png(mesh, content, layout, options, font));
}

}  // namespace harmonia
