// Two meshes side by side. Both views are rasterized in the left half's pixels, each with its
// camera (picture/mesh_rasterizer.h), and the right one is painted half the picture further right, a
// whole number of pixels: with one shared camera, whatever agrees between the two shapes looks
// exactly the same on both sides.
#include "picture/side_by_side_picture.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "harmonia/types.h"
#include "picture/mesh_rasterizer.h"
#include "picture/picture_format.h"
#include "picture/pixel_box.h"
#include "picture/raster_image.h"
#include "picture/text_rasterizer.h"

namespace harmonia::detail {
namespace {

constexpr Rgb kInk{0, 0, 0};

// The legend's entries in a row: swatch, gap, label, space before the next (in label sizes).
constexpr double kSwatchInLabels = 0.9;
constexpr double kSwatchGapInLabels = 0.4;
constexpr double kEntrySpaceInLabels = 1.5;

}  // namespace

// ---------------------------------------------------------------------------------------------
// Where things go

SideBySideFrame side_by_side_frame(const SideBySideLayout& picture, const TextRasterizer& font) {
  const double base = std::min(picture.width / 2.0, static_cast<double>(picture.height));
  SideBySideFrame frame;
  frame.margin = 0.025 * base;
  frame.label_size = std::max(11.0, base / 45.0);
  frame.half_width = picture.width / 2;
  double views_top = frame.margin;
  if (!picture.title.empty()) {
    const double title_size = 1.3 * frame.label_size;
    frame.title_size =
        fitted_size(font, picture.title, title_size, picture.width - 2.0 * frame.margin);
    frame.title_baseline = frame.margin + 0.95 * title_size;
    views_top += 1.5 * title_size;
  }
  frame.legend_baseline = picture.height - frame.margin - 0.3 * frame.label_size;
  // Without a legend the captions take its row.
  frame.caption_baseline = picture.legend.empty()
                               ? frame.legend_baseline
                               : frame.legend_baseline - 1.9 * frame.label_size;
  const double views_bottom = frame.caption_baseline - 1.4 * frame.label_size;
  // A margin on either side of each view: between them as much room as beside them together.
  frame.view = {frame.margin, views_top, frame.half_width - frame.margin,
                std::max(views_top + 1.0, views_bottom)};
  return frame;
}

namespace {

Eigen::AlignedBox3d bounding_box(const Eigen::MatrixX3d& positions) {
  Eigen::AlignedBox3d box;
  for (Eigen::Index v = 0; v < positions.rows(); ++v) box.extend(positions.row(v).transpose());
  return box;
}

// Looking along -z at the models' front, y up, `box` centred in the view and as large as it fits.
OrthographicCamera fitted_camera(const Eigen::AlignedBox3d& box, const PixelBox& view) {
  OrthographicCamera camera;  // Its default axes: toward +z, up +y, right +x.
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

// The left and right views' cameras.
std::pair<OrthographicCamera, OrthographicCamera> fitted_cameras(const PictureView& left,
                                                                 const PictureView& right,
                                                                 ViewCamera choice,
                                                                 const PixelBox& view) {
  const Eigen::AlignedBox3d left_box = bounding_box(left.positions);
  const Eigen::AlignedBox3d right_box = bounding_box(right.positions);
  if (choice == ViewCamera::per_view)
    return {fitted_camera(left_box, view), fitted_camera(right_box, view)};
  const OrthographicCamera shared = fitted_camera(left_box.merged(right_box), view);
  return {shared, shared};
}

// ---------------------------------------------------------------------------------------------
// Drawing

// The faces of a view, rasterized with its camera in the left view's pixels, and their colours
// shaded as they lie there.
struct ViewRaster {
  DepthBuffer buffer;
  std::vector<Rgb> colors;
};

ViewRaster rasterize_view(const PictureView& shown, const OrthographicCamera& camera,
                          const PixelBox& view, const RgbImage& image) {
  ViewRaster raster{DepthBuffer(camera, view, image.width(), image.height()),
                    std::vector<Rgb>(shown.face_colors.size())};
  for (Eigen::Index f = 0; f < shown.faces.rows(); ++f) {
    const std::array<Eigen::Vector3d, 3> corners = {
        Eigen::Vector3d(shown.positions.row(shown.faces(f, 0))),
        Eigen::Vector3d(shown.positions.row(shown.faces(f, 1))),
        Eigen::Vector3d(shown.positions.row(shown.faces(f, 2)))};
    raster.buffer.rasterize(static_cast<int>(f), corners);
    const Eigen::Vector3d normal = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    const auto i = static_cast<std::size_t>(f);
    raster.colors[i] = flat_shaded(shown.face_colors[i], normal, camera);
  }
  return raster;
}

// Both views, the right one `offset` pixels right of the left one.
void draw_views(RgbImage& image, const PictureView& left, const PictureView& right,
                const std::pair<OrthographicCamera, OrthographicCamera>& cameras,
                const PixelBox& view, int offset) {
  const ViewRaster left_raster = rasterize_view(left, cameras.first, view, image);
  const ViewRaster right_raster = rasterize_view(right, cameras.second, view, image);
  const bool edges = edges_fit(left_raster.buffer, left.face_colors.size());
  for (const auto& [raster, shift] :
       {std::pair{&left_raster, 0}, std::pair{&right_raster, offset}}) {
    paint_seen_faces(image, raster->buffer, raster->colors, {shift, 0});
    if (edges) blend_seen_edges(image, raster->buffer, {}, {shift, 0});
  }
}

void draw_centred_text(RgbImage& image, const TextRasterizer& font, const std::string& text,
                       double size, double centre_x, double baseline) {
  image.draw_text(font.rasterize(text, size), centre_x - 0.5 * font.width(text, size), baseline,
                  kInk);
}

// Both captions in one size, the largest at which each fits under its view.
void draw_captions(RgbImage& image, const std::array<std::string, 2>& captions,
                   const SideBySideFrame& frame, const TextRasterizer& font) {
  const double preferred = 1.1 * frame.label_size;
  const double size = std::min(fitted_size(font, captions[0], preferred, frame.view.width()),
                               fitted_size(font, captions[1], preferred, frame.view.width()));
  const double left_centre = 0.5 * (frame.view.left + frame.view.right);
  draw_centred_text(image, font, captions[0], size, left_centre, frame.caption_baseline);
  draw_centred_text(image, font, captions[1], size, left_centre + frame.half_width,
                    frame.caption_baseline);
}

// The entries in one row centred under the views, each a swatch of its colour (outlined, so that
// a light colour shows on the background) and its label; smaller text when the row is too wide.
void draw_legend(RgbImage& image, const std::vector<LegendEntry>& entries,
                 const SideBySideFrame& frame, const TextRasterizer& font) {
  if (entries.empty()) return;
  const auto row_width = [&](double size) {
    double width = kEntrySpaceInLabels * size * static_cast<double>(entries.size() - 1);
    for (const LegendEntry& entry : entries)
      width += (kSwatchInLabels + kSwatchGapInLabels) * size + font.width(entry.label, size);
    return width;
  };
  const double room = image.width() - 2.0 * frame.margin;
  double size = frame.label_size;
  if (row_width(size) > room) size *= room / row_width(size);
  const double swatch = kSwatchInLabels * size;
  const double swatch_top = frame.legend_baseline - 0.36 * size - 0.5 * swatch;
  double x = 0.5 * (image.width() - row_width(size));
  for (const LegendEntry& entry : entries) {
    const PixelBox box{x, swatch_top, x + swatch, swatch_top + swatch};
    image.fill_box(box, entry.color);
    image.outline_box(box, 1.0, kEdgeColor);
    x += swatch + kSwatchGapInLabels * size;
    image.draw_text(font.rasterize(entry.label, size), x, frame.legend_baseline, kInk);
    x += font.width(entry.label, size) + kEntrySpaceInLabels * size;
  }
}

}  // namespace

void draw_side_by_side_texts(RgbImage& image, const SideBySideFrame& frame,
                             const SideBySideLayout& layout,
                             const std::array<std::string, 2>& captions,
                             const TextRasterizer& font) {
  if (!layout.title.empty())
    image.draw_text(font.rasterize(layout.title, frame.title_size), frame.margin,
                    frame.title_baseline, kInk);
  draw_captions(image, captions, frame, font);
  draw_legend(image, layout.legend, frame, font);
}

OrthographicCamera front_camera(const Eigen::MatrixX3d& positions, const PixelBox& view) {
  return fitted_camera(bounding_box(positions), view);
}

std::string render_side_by_side_png(const PictureView& left, const PictureView& right,
                                    const SideBySideLayout& picture) {
  const TextRasterizer font;
  const SideBySideFrame frame = side_by_side_frame(picture, font);
  RgbImage image(picture.width, picture.height, kBackground);
  draw_views(image, left, right, fitted_cameras(left, right, picture.camera, frame.view),
             frame.view, frame.half_width);
  draw_side_by_side_texts(image, frame, picture, {left.caption, right.caption}, font);
  return image.encode_png();
}

// ---------------------------------------------------------------------------------------------
// The checks

void require_png(const std::filesystem::path& png, const std::string& caller) {
  // picture_format refuses what is neither PNG nor SVG; SVG is refused here.
  if (picture_format(png, caller) != PictureFormat::png)
    throw Error(Status::io_error, caller + ": '" + png.string() +
                                      "' asks for SVG; this picture is PNG only (use .png)");
}

void check_picture_size(int width, int height, const std::string& caller) {
  const auto refuse_outside = [&](const char* side, int value, int low) {
    if (value < low || value > kMaxPictureSide)
      throw Error(Status::invalid_input, caller + ": " + side + " " + std::to_string(value) +
                                             " is outside [" + std::to_string(low) + ", " +
                                             std::to_string(kMaxPictureSide) + "]");
  };
  refuse_outside("width", width, kMinPictureWidth);
  refuse_outside("height", height, kMinPictureHeight);
}

void check_face_corners(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count,
                        const std::string& caller) {
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int corner = 0; corner < 3; ++corner)
      if (faces(f, corner) < 0 || faces(f, corner) >= vertex_count)
        throw Error(Status::invalid_input, caller + ": face " + std::to_string(f) +
                                               " names vertex " +
                                               std::to_string(faces(f, corner)) +
                                               ", which does not exist");
}

void check_finite_positions(const Eigen::MatrixX3d& positions, const std::string& name,
                            const std::string& caller) {
  for (Eigen::Index v = 0; v < positions.rows(); ++v)
    if (!positions.row(v).allFinite())
      throw Error(Status::invalid_input, caller + ": " + name + " position of vertex " +
                                             std::to_string(v) + " is not finite");
}

}  // namespace harmonia::detail
