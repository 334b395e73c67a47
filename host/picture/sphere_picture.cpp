// Pictures of spherical maps: two opposite views of the unit sphere, each drawn by the software
// rasterizer of picture/mesh_rasterizer.h (orthographic projection, a depth buffer that also keeps
// which face is seen, flat Lambert shading), with the date line and the poles drawn over the
// visible surface, and the colour bar and legend below. Everything is drawn in a fixed order with
// integer blending (picture/raster_image.h), so the same map gives the same bytes.
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
#include "picture/color_bar_drawing.h"
#include "picture/color_map.h"
#include "picture/mesh_rasterizer.h"
#include "picture/pixel_box.h"
#include "picture/raster_image.h"
#include "picture/svg_markup.h"
#include "picture/text_rasterizer.h"

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

// One view: the camera looks at the sphere's centre; its scale is the sphere's radius in pixels.
struct View {
  detail::OrthographicCamera camera;
  PixelBox panel;  // Everything of this view is drawn inside.
  std::string heading;
  double heading_baseline = 0.0;
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
    views[0].camera.toward = Eigen::Vector3d::UnitZ();
    views[0].camera.up = Eigen::Vector3d::UnitY();
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
    const Eigen::Vector3d toward = std::cos(kViewTilt) * axis + std::sin(kViewTilt) * side;
    views[0].camera.toward = toward;
    views[0].camera.up = (axis - axis.dot(toward) * toward).normalized();
    views[0].heading = "north pole side, facing the date line";
    views[1].heading = "south pole side, facing away from it";
  }
  views[1].camera.toward = -views[0].camera.toward;
  views[1].camera.up = views[0].camera.up;
  for (View& view : views) view.camera.right = view.camera.up.cross(view.camera.toward);
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
    view.camera.centre = {0.5 * (view.panel.left + view.panel.right),
                          0.5 * (view.panel.top + view.panel.bottom)};
    // A little room outside the disk for the rings around marked triangles at its rim.
    view.camera.scale =
        std::max(2.0, 0.5 * std::min(view.panel.width(), view.panel.height()) - 0.6 * sizes.label);
    view.heading_baseline = heading_baseline;
  }
  return layout;
}

// ---------------------------------------------------------------------------------------------
// The surface in one view (picture/mesh_rasterizer.h)

// The depth buffer of a view: the square around the sphere's disk.
detail::DepthBuffer view_buffer(const View& view, int image_width, int image_height) {
  const Eigen::Vector2d& centre = view.camera.centre;
  const double radius = view.camera.scale;
  return detail::DepthBuffer(view.camera,
                             {centre.x() - radius, centre.y() - radius, centre.x() + radius,
                              centre.y() + radius},
                             image_width, image_height);
}

// Whether a point of the unit sphere is in front of everything drawn at its pixel. The sphere
// bulges out of its chord triangles, so a point of the front half never hides behind them; the
// tolerance covers the pull of marked triangles.
bool visible(const detail::DepthBuffer& buffer, const Eigen::Vector3d& point) {
  const Eigen::Vector2d at = buffer.camera().pixel(point);
  const int x = static_cast<int>(std::floor(at.x())) - buffer.left();
  const int y = static_cast<int>(std::floor(at.y())) - buffer.top();
  const double depth = buffer.camera().depth(point);
  constexpr double tolerance = kMarkedDepthBias + 1e-3;
  if (buffer.face(x, y) < 0)
    return depth >= -tolerance;  // Off the drawn surface: near the rim, seen if in front.
  return depth >= buffer.depth(x, y) - tolerance;
}

std::array<Eigen::Vector3d, 3> face_corners(const Mesh& mesh, const SphereContent& content,
                                            Eigen::Index f) {
  return {Eigen::Vector3d(content.points.row(mesh.faces(f, 0))),
          Eigen::Vector3d(content.points.row(mesh.faces(f, 1))),
          Eigen::Vector3d(content.points.row(mesh.faces(f, 2)))};
}

// A face's colour, shaded. The normal's sign does not matter (flat_shaded lights both sides): a
// face turned over is drawn in its marker colour anyway. A degenerate chord triangle is lit as the
// sphere is where it lies.
Rgb shaded(const Rgb& color, const std::array<Eigen::Vector3d, 3>& corners, const View& view) {
  Eigen::Vector3d normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
  if (!(normal.norm() > 0.0)) normal = corners[0] + corners[1] + corners[2];
  return detail::flat_shaded(color, normal, view.camera);
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
void draw_surface(detail::RgbImage& image, const detail::DepthBuffer& buffer, const View& view,
                  const Mesh& mesh, const SphereContent& content) {
  std::vector<Rgb> color(content.fill.size());
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const auto i = static_cast<std::size_t>(f);
    if (content.drawable[i])
      color[i] = content.marked[i] ? content.fill[i]
                                   : shaded(content.fill[i], face_corners(mesh, content, f), view);
  }
  detail::paint_seen_faces(image, buffer, color);
  if (detail::edges_fit(buffer, color.size()))
    detail::blend_seen_edges(image, buffer, content.marked);  // Marked ones get an outline.
  for (int y = 0; y < buffer.height(); ++y) {
    for (int x = 0; x < buffer.width(); ++x) {
      const int f = buffer.face(x, y);
      if (f < 0 || !content.marked[static_cast<std::size_t>(f)]) continue;
      const bool border = buffer.face(x + 1, y) != f || buffer.face(x - 1, y) != f ||
                          buffer.face(x, y + 1) != f || buffer.face(x, y - 1) != f;
      if (border) image.set(buffer.left() + x, buffer.top() + y, detail::kFlippedOutline);
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
    if (view.camera.depth(centroid) <= 0.0) continue;  // The other view shows it.
    draw_ring(image, view.camera.pixel(centroid), radius, width, detail::kFlippedOutline,
              view.panel);
  }
}

// The date line's great-circle arcs, sampled a few pixels apart, cut into the runs the depth test
// lets through; all dark edges first, then all yellow cores, so that crossings stay clean.
void draw_date_line(detail::RgbImage& image, const detail::DepthBuffer& buffer, const View& view,
                    const SphereContent& content, const std::vector<int>& date_line,
                    const Sizes& sizes) {
  std::vector<std::vector<Eigen::Vector2d>> runs(1);
  const auto add_sample = [&](const Eigen::Vector3d& point) {
    if (visible(buffer, point)) {
      runs.back().push_back(view.camera.pixel(point));
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
    const int samples = std::max(1, static_cast<int>(std::ceil(angle * view.camera.scale / 3.0)));
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

void draw_poles(detail::RgbImage& image, const detail::DepthBuffer& buffer, const View& view,
                const SphereContent& content, const SpherePictureOptions& options,
                const Sizes& sizes, const detail::TextRasterizer& font) {
  for (const auto& [pole, name] :
       {std::pair{options.north_pole, "N"}, std::pair{options.south_pole, "S"}}) {
    const std::optional<Eigen::Vector3d> point = pole_point(content, pole);
    if (point && visible(buffer, *point))
      draw_pole_marker(image, view.camera.pixel(*point), name, sizes, font, view.panel);
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
                    view.camera.centre.x() - 0.5 * font.width(view.heading, heading_size),
                    view.heading_baseline, kInk);
    detail::DepthBuffer buffer = view_buffer(view, layout.width, layout.height);
    for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
      const auto i = static_cast<std::size_t>(f);
      if (!content.drawable[i]) continue;
      buffer.rasterize(static_cast<int>(f), face_corners(mesh, content, f),
                       content.marked[i] ? kMarkedDepthBias : 0.0);
    }
    draw_surface(image, buffer, view, mesh, content);
    draw_date_line(image, buffer, view, content, options.date_line, layout.sizes);
    draw_marker_rings(image, view, mesh, content, layout.sizes);
    draw_poles(image, buffer, view, content, options, layout.sizes, font);
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
