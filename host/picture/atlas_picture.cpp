// The picture of a texture atlas: the atlas square coloured by distortion beside the mesh wearing
// a checker through the atlas, in the frame of the side-by-side pictures
// (picture/side_by_side_picture.h: title, captions, legend), the right view rasterized with
// picture/mesh_rasterizer.h. The distortion is the layout picture's (harmonia/picture.h): the same
// metrics, the same colours.
#include "harmonia/atlas_picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/LU>

#include "atlas/atlas_metrics.h"
#include "harmonia/metrics.h"
#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "picture/color_map.h"
#include "picture/mesh_rasterizer.h"
#include "picture/pixel_box.h"
#include "picture/raster_image.h"
#include "picture/side_by_side_picture.h"
#include "picture/svg_markup.h"
#include "picture/text_rasterizer.h"
#include "mesh/edge_table.h"
#include "planar/uv_layout_checks.h"

namespace harmonia {
namespace {

using detail::PixelBox;
using detail::Rgb;

const std::string kCaller = "write_atlas_picture";

constexpr Rgb kInk{0, 0, 0};
// Dark enough to stand out against white and red triangles alike.
constexpr Rgb kChartBoundaryColor{40, 40, 40};
// The checker: a cream and a slate blue, apart from each other under any shading and from the
// grey background.
constexpr Rgb kCheckerLight{250, 236, 200};
constexpr Rgb kCheckerDark{60, 84, 130};

// ---------------------------------------------------------------------------------------------
// The checks

void validate(const Mesh& mesh, const TextureAtlas& atlas, const AtlasPictureOptions& options) {
  const auto refuse = [](const std::string& problem) {
    throw Error(Status::invalid_input, kCaller + ": " + problem);
  };
  detail::check_picture_size(options.width, options.height, kCaller);
  // Row counts, chart ids, the charts' face lists, the resolution, the faces' vertex indices.
  if (const std::string mismatch = detail::atlas_mismatch(mesh, atlas); !mismatch.empty())
    refuse(mismatch);
  detail::check_finite_positions(mesh.vertices, "mesh", kCaller);
  for (Eigen::Index f = 0; f < atlas.corner_uv.rows(); ++f) {
    for (int corner = 0; corner < 3; ++corner) {
      const double u = atlas.corner_uv(f, 2 * corner), v = atlas.corner_uv(f, 2 * corner + 1);
      const std::string where = "face " + std::to_string(f) + " corner " + std::to_string(corner);
      if (!std::isfinite(u) || !std::isfinite(v)) refuse(where + " has a UV that is not finite");
      if (u < 0.0 || u > 1.0 || v < 0.0 || v > 1.0)
        refuse(where + " has UV (" + std::to_string(u) + ", " + std::to_string(v) +
               "), outside the atlas' [0, 1] square");
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The atlas as drawn

struct AtlasContent {
  // The corners as UV rows, one per chart, vertex and position: faces of a chart that agree at a
  // vertex share its row, so the layout's edges used by one face are the chart boundaries.
  detail::AtlasUvLayout layout;
  std::vector<Rgb> fill;      // Per face: the colour of its conformal distortion.
  std::vector<char> flipped;  // Per face: clockwise or of zero area in UV.
  int flipped_count = 0;
  int faces_without_chart = 0;
  std::vector<std::array<int, 2>> chart_boundary;  // Edges as pairs of layout rows.
};

bool in_chart(const TextureAtlas& atlas, Eigen::Index face) {
  return atlas.chart_of_face[static_cast<std::size_t>(face)] >= 0;
}

// The edges of the layout used by one face of a chart: where the face across is in another
// chart or there is none (or, in a broken atlas, where a chart's corners disagree).
std::vector<std::array<int, 2>> chart_boundary_edges(const detail::AtlasUvLayout& layout,
                                                     const TextureAtlas& atlas) {
  Mesh layout_mesh;  // The layout's faces over its UV rows; EdgeTable reads only the row count.
  layout_mesh.vertices.resize(layout.uv.rows(), 3);
  layout_mesh.faces = layout.uv_faces;
  const detail::EdgeTable edges(layout_mesh);
  std::vector<std::array<int, 2>> boundary;
  for (int edge = 0; edge < edges.size(); ++edge)
    if (edges.face_count(edge) == 1 && in_chart(atlas, edges.uses(edge).front().face()))
      boundary.push_back({edges.first(edge), edges.second(edge)});
  return boundary;
}

AtlasContent atlas_content(const Mesh& mesh, const TextureAtlas& atlas) {
  AtlasContent content;
  content.layout = detail::atlas_uv_layout(mesh, atlas);
  const detail::AtlasUvLayout& layout = content.layout;
  // sigma1/sigma2 per triangle, exactly as `harmonia eval` and the layout picture measure it, in
  // texels (u times the width, v times the height: a non-square atlas' own proportions).
  Eigen::MatrixX2d texels = layout.uv;
  texels.col(0) *= atlas.resolution;
  texels.col(1) *= atlas.height_texels();
  const DistortionMetrics metrics = evaluate_map(mesh, texels, layout.uv_faces);
  const std::vector<double> areas = detail::signed_uv_areas(layout.uv, layout.uv_faces);
  const auto faces = static_cast<std::size_t>(mesh.faces.rows());
  content.fill.resize(faces);
  content.flipped.resize(faces);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    const auto i = static_cast<std::size_t>(f);
    if (!in_chart(atlas, f)) {
      ++content.faces_without_chart;
      continue;
    }
    content.flipped[i] = detail::classify_uv_triangle(layout.uv, layout.uv_faces, f, areas[i]) !=
                         detail::TriangleState::positive;
    content.flipped_count += content.flipped[i];
    content.fill[i] = detail::conformal_color(metrics.face_conformal_distortion[f]);
  }
  content.chart_boundary = chart_boundary_edges(layout, atlas);
  return content;
}

// ---------------------------------------------------------------------------------------------
// Left: the atlas square

// The atlas' [0, 1]^2 in pixels: a rectangle of the atlas' shape (a square for a square atlas)
// centred in the view, with room for its outline around.
struct AtlasSquare {
  PixelBox box;
  double outline_width = 1.0;

  [[nodiscard]] Eigen::Vector2d pixel(const Eigen::Vector2d& uv) const {
    return {box.left + uv.x() * box.width(), box.bottom - uv.y() * box.height()};  // v up.
  }
};

AtlasSquare atlas_square(const PixelBox& view, double line_width, const TextureAtlas& atlas) {
  const double aspect = static_cast<double>(atlas.resolution) / atlas.height_texels();  // width / height
  const double room_width = std::max(1.0, view.width() - 2.0 * line_width);
  const double room_height = std::max(1.0, view.height() - 2.0 * line_width);
  const double width = std::min(room_width, room_height * aspect), height = width / aspect;
  const double left = 0.5 * (view.left + view.right - width);
  const double top = 0.5 * (view.top + view.bottom - height);
  return {{left, top, left + width, top + height}, line_width};
}

std::array<Eigen::Vector2d, 3> uv_triangle_pixels(const AtlasSquare& square,
                                                  const detail::AtlasUvLayout& layout,
                                                  Eigen::Index face) {
  std::array<Eigen::Vector2d, 3> corners;
  for (int corner = 0; corner < 3; ++corner)
    corners[static_cast<std::size_t>(corner)] =
        square.pixel(layout.uv.row(layout.uv_faces(face, corner)).transpose());
  return corners;
}

// The triangles in their colours, the chart boundaries over them, the flipped triangles last (so
// that no neighbour hides them), and the square's outline around everything.
void draw_atlas(detail::RgbImage& image, const AtlasContent& content, const TextureAtlas& atlas,
                const AtlasSquare& square) {
  const detail::AtlasUvLayout& layout = content.layout;
  const Eigen::Index faces = layout.uv_faces.rows();
  for (Eigen::Index f = 0; f < faces; ++f)
    if (in_chart(atlas, f) && !content.flipped[static_cast<std::size_t>(f)])
      image.fill_triangle(uv_triangle_pixels(square, layout, f),
                          content.fill[static_cast<std::size_t>(f)]);
  const double boundary_width = std::max(1.5, square.box.width() / 400.0);
  for (const auto& [from, to] : content.chart_boundary) {
    const Eigen::Vector2d a = square.pixel(layout.uv.row(from).transpose());
    const Eigen::Vector2d b = square.pixel(layout.uv.row(to).transpose());
    // Clipped to the segment's own box: the stroke's work is then proportional to its length.
    const double reach = boundary_width + 1.0;
    const PixelBox clip{std::min(a.x(), b.x()) - reach, std::min(a.y(), b.y()) - reach,
                        std::max(a.x(), b.x()) + reach, std::max(a.y(), b.y()) + reach};
    image.stroke_polyline({a, b}, boundary_width, kChartBoundaryColor, clip);
  }
  for (Eigen::Index f = 0; f < faces; ++f) {
    if (!in_chart(atlas, f) || !content.flipped[static_cast<std::size_t>(f)]) continue;
    const std::array<Eigen::Vector2d, 3> corners = uv_triangle_pixels(square, layout, f);
    image.fill_triangle(corners, detail::kFlippedFill);
    for (std::size_t corner = 0; corner < 3; ++corner)
      image.draw_line(corners[corner], corners[(corner + 1) % 3], detail::kFlippedOutline);
  }
  const PixelBox& box = square.box;
  const double line = square.outline_width;
  image.outline_box({box.left - line, box.top - line, box.right + line, box.bottom + line}, line,
                    kInk);
}

// ---------------------------------------------------------------------------------------------
// Right: the mesh with the checker

// What a pixel needs of the face it shows: the map from its projected triangle's barycentric
// coordinates to the UV, and its two checker colours, shaded as the face lies.
struct TexturedFace {
  Eigen::Vector2d first_pixel;           // The projection of corner 0.
  Eigen::Matrix2d pixel_to_barycentric;  // (pixel - first_pixel) -> (b1, b2); b0 = 1 - b1 - b2.
  std::array<Eigen::Vector2d, 3> corner_uv;
  Rgb light;
  Rgb dark;
};

TexturedFace textured_face(const Mesh& mesh, const TextureAtlas& atlas, Eigen::Index face,
                           const detail::OrthographicCamera& camera) {
  std::array<Eigen::Vector3d, 3> corners;
  TexturedFace textured;
  for (int corner = 0; corner < 3; ++corner) {
    const auto k = static_cast<std::size_t>(corner);
    corners[k] = mesh.vertices.row(mesh.faces(face, corner)).transpose();
    textured.corner_uv[k] = {atlas.corner_uv(face, 2 * corner),
                             atlas.corner_uv(face, 2 * corner + 1)};
  }
  textured.first_pixel = camera.pixel(corners[0]);
  Eigen::Matrix2d edges;  // The projected edges from corner 0, as columns.
  edges << camera.pixel(corners[1]) - textured.first_pixel,
      camera.pixel(corners[2]) - textured.first_pixel;
  // A face seen edge-on covers no pixel centre (DepthBuffer::rasterize), so this is never used
  // where the inverse does not exist.
  textured.pixel_to_barycentric = edges.inverse();
  const Eigen::Vector3d normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
  const bool charted = in_chart(atlas, face);
  textured.light = detail::flat_shaded(charted ? kCheckerLight : detail::kUndefinedFill, normal,
                                       camera);
  textured.dark = detail::flat_shaded(charted ? kCheckerDark : detail::kUndefinedFill, normal,
                                      camera);
  return textured;
}

// The checker square that `uv` falls in is dark when its column and row add up to an odd number.
// The squares are square in texels: kAtlasCheckerSquares along the width, as many rows as the
// height holds (`rows_per_column` = height / width).
bool in_dark_square(Eigen::Vector2d uv, double rows_per_column) {
  // Inside a face the UV lies in the atlas; in a face seen almost edge-on rounding may carry it
  // out (or make it NaN), so it is brought back before it becomes a square's index.
  if (!uv.allFinite()) uv.setZero();
  uv = uv.cwiseMax(0.0).cwiseMin(1.0);
  const auto column = static_cast<int>(std::floor(uv.x() * kAtlasCheckerSquares));
  const auto row = static_cast<int>(std::floor(uv.y() * kAtlasCheckerSquares * rows_per_column));
  return (column + row) % 2 == 1;
}

// The mesh rasterized in the left view's pixels and painted `offset` pixels further right, as the
// side-by-side pictures paint their right view.
void draw_checkered_mesh(detail::RgbImage& image, const Mesh& mesh, const TextureAtlas& atlas,
                         const PixelBox& view, int offset) {
  const detail::OrthographicCamera camera = detail::front_camera(mesh.vertices, view);
  detail::DepthBuffer buffer(camera, view, image.width(), image.height());
  std::vector<TexturedFace> textured;
  textured.reserve(static_cast<std::size_t>(mesh.faces.rows()));
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    buffer.rasterize(static_cast<int>(f),
                     {Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, 0))),
                      Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, 1))),
                      Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, 2)))});
    textured.push_back(textured_face(mesh, atlas, f, camera));
  }
  for (int y = 0; y < buffer.height(); ++y) {
    for (int x = 0; x < buffer.width(); ++x) {
      const int f = buffer.face(x, y);
      if (f < 0) continue;
      const TexturedFace& face = textured[static_cast<std::size_t>(f)];
      const Eigen::Vector2d centre(buffer.left() + x + 0.5, buffer.top() + y + 0.5);
      const Eigen::Vector2d b = face.pixel_to_barycentric * (centre - face.first_pixel);
      const Eigen::Vector2d uv = (1.0 - b.x() - b.y()) * face.corner_uv[0] +
                                 b.x() * face.corner_uv[1] + b.y() * face.corner_uv[2];
      image.set(buffer.left() + x + offset, buffer.top() + y,
                in_dark_square(uv, static_cast<double>(atlas.height_texels()) / atlas.resolution) ? face.dark
                                                                                                  : face.light);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The texts

std::string atlas_caption(const TextureAtlas& atlas) {
  const std::size_t charts = atlas.charts.size();
  std::string caption = "atlas: " + std::to_string(charts) + (charts == 1 ? " chart" : " charts");
  if (atlas.metrics.coverage > 0.0)
    caption += ", " + detail::fixed_number(100.0 * atlas.metrics.coverage, 1) + " % covered";
  return caption;
}

// The distortion colours at the layout picture's colour-bar ticks, then what else is drawn.
std::vector<detail::LegendEntry> legend_entries(const AtlasContent& content) {
  const detail::ColorBar bar = detail::conformal_color_bar();
  std::vector<detail::LegendEntry> entries;
  for (const detail::ColorBarTick& tick : bar.ticks)
    entries.push_back({bar.color_at(tick.position),
                       entries.empty() ? "σ1/σ2 = " + tick.label : tick.label});
  entries.push_back({kChartBoundaryColor, "chart boundary"});
  if (content.flipped_count > 0)
    entries.push_back({detail::kFlippedFill, "flipped or of zero area (" +
                                                 std::to_string(content.flipped_count) + ")"});
  if (content.faces_without_chart > 0)
    entries.push_back({detail::kUndefinedFill,
                       "no chart (" + std::to_string(content.faces_without_chart) + ")"});
  return entries;
}

std::string render_png(const Mesh& mesh, const TextureAtlas& atlas,
                       const AtlasPictureOptions& options) {
  const AtlasContent content = atlas_content(mesh, atlas);
  detail::SideBySideLayout layout;
  layout.width = options.width;
  layout.height = options.height;
  layout.title = options.title;
  layout.legend = legend_entries(content);
  const detail::TextRasterizer font;
  const detail::SideBySideFrame frame = detail::side_by_side_frame(layout, font);
  detail::RgbImage image(options.width, options.height, detail::kBackground);
  const double outline_width = std::max(1.0, frame.label_size / 12.0);
  draw_atlas(image, content, atlas, atlas_square(frame.view, outline_width, atlas));
  draw_checkered_mesh(image, mesh, atlas, frame.view, frame.half_width);
  detail::draw_side_by_side_texts(image, frame, layout,
                                  {atlas_caption(atlas), "checker through the atlas"}, font);
  return image.encode_png();
}

}  // namespace

void write_atlas_picture(const std::filesystem::path& png, const Mesh& mesh,
                         const TextureAtlas& atlas, const AtlasPictureOptions& options) {
  detail::require_png(png, kCaller);  // Before any work.
  validate(mesh, atlas, options);
  detail::write_file_atomically(png, render_png(mesh, atlas, options));
}

}  // namespace harmonia
