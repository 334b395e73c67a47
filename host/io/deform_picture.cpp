// The "before and after" picture of a surface edit. Both shapes are rasterized with one camera
// (io/mesh_rasterizer.h) in the left view's pixels and the deformed one is painted half the picture
// further right, a whole number of pixels, so that whatever the edit did not move looks exactly
// the same on both sides. Everything is drawn in a fixed order with integer blending
// (io/raster_image.h), so the same arguments give the same bytes.
#include "harmonia/deform_picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "io/color_map.h"
#include "io/mesh_rasterizer.h"
#include "io/picture_format.h"
#include "io/pixel_box.h"
#include "io/raster_image.h"
#include "io/text_rasterizer.h"

namespace harmonia {
namespace {

using detail::PixelBox;
using detail::Rgb;

const std::string kCaller = "write_deform_picture";

constexpr Rgb kInk{0, 0, 0};
constexpr Rgb kFreeColor{210, 210, 210};
constexpr Rgb kFixedColor{105, 145, 225};
// The handles' tints, cycled: warm hues that stay apart from each other, from the free grey and
// from the fixed blue.
constexpr std::array<Rgb, 6> kHandleColors = {{{240, 125, 45},
                                               {215, 55, 55},
                                               {235, 185, 40},
                                               {195, 75, 140},
                                               {160, 95, 50},
                                               {250, 150, 120}}};

// The legend's entries in a row: swatch, gap, label, space before the next (in label sizes).
constexpr double kSwatchInLabels = 0.9;
constexpr double kSwatchGapInLabels = 0.4;
constexpr double kEntrySpaceInLabels = 1.5;

// ---------------------------------------------------------------------------------------------
// The edit as drawn

Rgb role_color(int role) {
  if (role == kDeformRoleFixed) return kFixedColor;
  if (role >= 0) return kHandleColors[static_cast<std::size_t>(role) % kHandleColors.size()];
  return kFreeColor;
}

// The first row with a coordinate that is not finite, -1 when there is none.
Eigen::Index first_non_finite_row(const Eigen::MatrixX3d& positions) {
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    if (!positions.row(v).allFinite()) return v;
  return -1;
}

void validate(const Mesh& rest, const Eigen::MatrixX3d& deformed,
              const std::vector<int>& vertex_roles, const DeformPictureOptions& options) {
  const auto refuse = [](const std::string& problem) {
    throw Error(Status::invalid_input, kCaller + ": " + problem);
  };
  if (options.width < 320 || options.width > 16384)
    refuse("width " + std::to_string(options.width) + " is outside [320, 16384]");
  if (options.height < 240 || options.height > 16384)
    refuse("height " + std::to_string(options.height) + " is outside [240, 16384]");
  const Eigen::Index vertices = rest.vertices.rows();
  const std::string per_vertex = " for " + std::to_string(vertices) + " vertices";
  if (deformed.rows() != vertices)
    refuse(std::to_string(deformed.rows()) + " deformed positions" + per_vertex);
  if (static_cast<Eigen::Index>(vertex_roles.size()) != vertices)
    refuse(std::to_string(vertex_roles.size()) + " vertex roles" + per_vertex);
  for (std::size_t v = 0; v < vertex_roles.size(); ++v)
    if (vertex_roles[v] < kDeformRoleFixed)
      refuse("vertex " + std::to_string(v) + " has role " + std::to_string(vertex_roles[v]) +
             " (-1 free, -2 fixed, a handle's index from 0)");
  for (Eigen::Index f = 0; f < rest.faces.rows(); ++f)
    for (int corner = 0; corner < 3; ++corner)
      if (rest.faces(f, corner) < 0 || rest.faces(f, corner) >= vertices)
        refuse("face " + std::to_string(f) + " names vertex " +
               std::to_string(rest.faces(f, corner)) + ", which does not exist");
  for (const auto& [positions, name] : {std::pair{&rest.vertices, "rest"},
                                        std::pair{&deformed, "deformed"}}) {
    const Eigen::Index v = first_non_finite_row(*positions);
    if (v >= 0) refuse(std::string(name) + " position of vertex " + std::to_string(v) +
                       " is not finite");
  }
}

// A face takes its corners' role when all three share it; a face across roles is free.
std::vector<Rgb> face_colors(const Mesh& mesh, const std::vector<int>& vertex_roles) {
  std::vector<Rgb> colors(static_cast<std::size_t>(mesh.faces.rows()));
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const int role = vertex_roles[mesh.faces(f, 0)];
    const bool shared =
        vertex_roles[mesh.faces(f, 1)] == role && vertex_roles[mesh.faces(f, 2)] == role;
    colors[static_cast<std::size_t>(f)] = role_color(shared ? role : kDeformRoleFree);
  }
  return colors;
}

struct LegendEntry {
  Rgb color;
  std::string label;
};

// The roles that occur: free, fixed, then the handles by index.
std::vector<LegendEntry> legend_entries(const std::vector<int>& vertex_roles) {
  const std::set<int> roles(vertex_roles.begin(), vertex_roles.end());
  std::vector<LegendEntry> entries;
  if (roles.contains(kDeformRoleFree)) entries.push_back({kFreeColor, "free"});
  if (roles.contains(kDeformRoleFixed)) entries.push_back({kFixedColor, "fixed"});
  for (const int role : roles)
    if (role >= 0) entries.push_back({role_color(role), "handle " + std::to_string(role)});
  return entries;
}

// ---------------------------------------------------------------------------------------------
// Where things go

struct Layout {
  double margin = 0.0;
  double label_size = 0.0;  // Font sizes, pixels per em.
  double title_size = 0.0;
  double title_baseline = 0.0;
  PixelBox view;        // The left view; the right one lies `half_width` pixels further right.
  int half_width = 0;   // Whole pixels, so that both views fall on the pixel grid alike.
  double caption_baseline = 0.0;  // "before" and "after", centred under the views.
  double legend_baseline = 0.0;
};

Layout lay_out(const DeformPictureOptions& options, const detail::TextRasterizer& font) {
  const double base = std::min(options.width / 2.0, static_cast<double>(options.height));
  Layout layout;
  layout.margin = 0.025 * base;
  layout.label_size = std::max(11.0, base / 45.0);
  layout.half_width = options.width / 2;
  double views_top = layout.margin;
  if (!options.title.empty()) {
    const double title_size = 1.3 * layout.label_size;
    layout.title_size =
        detail::fitted_size(font, options.title, title_size, options.width - 2.0 * layout.margin);
    layout.title_baseline = layout.margin + 0.95 * title_size;
    views_top += 1.5 * title_size;
  }
  layout.legend_baseline = options.height - layout.margin - 0.3 * layout.label_size;
  layout.caption_baseline = layout.legend_baseline - 1.9 * layout.label_size;
  const double views_bottom = layout.caption_baseline - 1.4 * layout.label_size;
  // A margin on either side of each view: between them as much room as beside them together.
  layout.view = {layout.margin, views_top, layout.half_width - layout.margin,
                 std::max(views_top + 1.0, views_bottom)};
  return layout;
}

// One camera for both views: looking along -z at the models' front, y up, the union of the two
// shapes' bounding boxes centred in the left view and as large as it fits.
detail::OrthographicCamera fitted_camera(const Eigen::MatrixX3d& rest,
                                         const Eigen::MatrixX3d& deformed, const PixelBox& view) {
  Eigen::AlignedBox3d box;
  for (const Eigen::MatrixX3d* positions : {&rest, &deformed})
    for (Eigen::Index v = 0; v < positions->rows(); ++v) box.extend(positions->row(v).transpose());
  detail::OrthographicCamera camera;  // Its default axes: toward +z, up +y, right +x.
  camera.centre = {0.5 * (view.left + view.right), 0.5 * (view.top + view.bottom)};
  if (box.isEmpty()) return camera;
  camera.target = box.center();
  const Eigen::Vector3d extent = box.sizes();
  double scale = std::numeric_limits<double>::infinity();
  if (extent.x() > 0.0) scale = std::min(scale, view.width() / extent.x());
  if (extent.y() > 0.0) scale = std::min(scale, view.height() / extent.y());
  camera.scale = std::isfinite(scale) ? scale : 1.0;  // A point or a segment along z: any scale.
  return camera;
}

// ---------------------------------------------------------------------------------------------
// Drawing

// The faces of `mesh` at `positions`, rasterized with the camera in the left view's pixels, and
// their colours shaded as they lie there.
struct ViewRaster {
  detail::DepthBuffer buffer;
  std::vector<Rgb> colors;
};

ViewRaster rasterize_view(const Mesh& mesh, const Eigen::MatrixX3d& positions,
                          const std::vector<Rgb>& fill, const detail::OrthographicCamera& camera,
                          const PixelBox& view, const detail::RgbImage& image) {
  ViewRaster raster{detail::DepthBuffer(camera, view, image.width(), image.height()),
                    std::vector<Rgb>(fill.size())};
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const std::array<Eigen::Vector3d, 3> corners = {
        Eigen::Vector3d(positions.row(mesh.faces(f, 0))),
        Eigen::Vector3d(positions.row(mesh.faces(f, 1))),
        Eigen::Vector3d(positions.row(mesh.faces(f, 2)))};
    raster.buffer.rasterize(static_cast<int>(f), corners);
    const Eigen::Vector3d normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    const auto i = static_cast<std::size_t>(f);
    raster.colors[i] = detail::flat_shaded(fill[i], normal, camera);
  }
  return raster;
}

// Both views, the deformed one `offset` pixels right of the rest one. Edges are drawn in both or
// in neither, as the rest view's faces allow, so that the two look alike.
void draw_views(detail::RgbImage& image, const Mesh& rest, const Eigen::MatrixX3d& deformed,
                const std::vector<Rgb>& fill, const detail::OrthographicCamera& camera,
                const PixelBox& view, int offset) {
  const ViewRaster before = rasterize_view(rest, rest.vertices, fill, camera, view, image);
  const ViewRaster after = rasterize_view(rest, deformed, fill, camera, view, image);
  const bool edges = detail::edges_fit(before.buffer, fill.size());
  for (const auto& [raster, shift] : {std::pair{&before, 0}, std::pair{&after, offset}}) {
    detail::paint_seen_faces(image, raster->buffer, raster->colors, {shift, 0});
    if (edges) detail::blend_seen_edges(image, raster->buffer, {}, {shift, 0});
  }
}

void draw_centred_text(detail::RgbImage& image, const detail::TextRasterizer& font,
                       const std::string& text, double size, double centre_x, double baseline) {
  image.draw_text(font.rasterize(text, size), centre_x - 0.5 * font.width(text, size), baseline,
                  kInk);
}

// The entries in one row centred under the views, each a swatch of its colour (outlined, so that
// the light grey shows on the background) and its label; smaller text when the row is too wide.
void draw_legend(detail::RgbImage& image, const std::vector<LegendEntry>& entries,
                 const Layout& layout, const detail::TextRasterizer& font) {
  if (entries.empty()) return;
  const auto row_width = [&](double size) {
    double width = kEntrySpaceInLabels * size * static_cast<double>(entries.size() - 1);
    for (const LegendEntry& entry : entries)
      width += (kSwatchInLabels + kSwatchGapInLabels) * size + font.width(entry.label, size);
    return width;
  };
  const double room = image.width() - 2.0 * layout.margin;
  double size = layout.label_size;
  if (row_width(size) > room) size *= room / row_width(size);
  const double swatch = kSwatchInLabels * size;
  const double swatch_top = layout.legend_baseline - 0.36 * size - 0.5 * swatch;
  double x = 0.5 * (image.width() - row_width(size));
  for (const LegendEntry& entry : entries) {
    const PixelBox box{x, swatch_top, x + swatch, swatch_top + swatch};
    image.fill_box(box, entry.color);
    image.outline_box(box, 1.0, detail::kEdgeColor);
    x += swatch + kSwatchGapInLabels * size;
    image.draw_text(font.rasterize(entry.label, size), x, layout.legend_baseline, kInk);
    x += font.width(entry.label, size) + kEntrySpaceInLabels * size;
  }
}

std::string render_png(const Mesh& rest, const Eigen::MatrixX3d& deformed,
                       const std::vector<int>& vertex_roles, const DeformPictureOptions& options,
                       const detail::TextRasterizer& font) {
  const Layout layout = lay_out(options, font);
  detail::RgbImage image(options.width, options.height, detail::kBackground);
  if (!options.title.empty())
    image.draw_text(font.rasterize(options.title, layout.title_size), layout.margin,
                    layout.title_baseline, kInk);
  const detail::OrthographicCamera camera = fitted_camera(rest.vertices, deformed, layout.view);
  const std::vector<Rgb> fill = face_colors(rest, vertex_roles);
  draw_views(image, rest, deformed, fill, camera, layout.view, layout.half_width);
  const double caption_size =
      detail::fitted_size(font, "before", 1.1 * layout.label_size, layout.view.width());
  const double left_centre = 0.5 * (layout.view.left + layout.view.right);
  draw_centred_text(image, font, "before", caption_size, left_centre, layout.caption_baseline);
  draw_centred_text(image, font, "after", caption_size, left_centre + layout.half_width,
                    layout.caption_baseline);
  draw_legend(image, legend_entries(vertex_roles), layout, font);
  return image.encode_png();
}

}  // namespace

void write_deform_picture(const std::filesystem::path& png, const Mesh& rest,
                          const Eigen::MatrixX3d& deformed, const std::vector<int>& vertex_roles,
                          const DeformPictureOptions& options) {
  // Before any work: only PNG, since the views are rasterized.
  if (detail::picture_format(png, kCaller) != detail::PictureFormat::png)
    throw Error(Status::io_error, kCaller + ": '" + png.string() +
                                      "' asks for SVG; this picture is PNG only (use .png)");
  validate(rest, deformed, vertex_roles, options);
  const detail::TextRasterizer font;
  detail::write_file_atomically(png, render_png(rest, deformed, vertex_roles, options, font));
}

}  // namespace harmonia
