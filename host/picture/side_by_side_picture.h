#pragma once
// Internal: a picture of two meshes side by side (deform_picture.cpp: before and after an edit;
// transfer_picture.cpp: a source and a target). Each half shows one view, flat shaded and
// depth-tested, looking along -z at the models' +z side (their front), y up; a caption under each
// view, an optional legend row below, an optional title on top. The PNG is rasterized in-house
// (picture/mesh_rasterizer.h) and drawn in a fixed order with integer blending, so the same arguments
// give the same bytes. Also the frame alone (where the views go, and the texts around them) for a
// picture that draws its own views (atlas_picture.cpp), and the argument checks that every such
// picture makes.

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "picture/color_map.h"
#include "picture/mesh_rasterizer.h"
#include "picture/pixel_box.h"
#include "picture/raster_image.h"
#include "picture/text_rasterizer.h"

namespace harmonia::detail {

// What one half shows: the faces at `positions`, each in its colour, and a caption under it.
// The references must outlive the call that draws them.
struct PictureView {
  const Eigen::MatrixX3i& faces;
  const Eigen::MatrixX3d& positions;  // #V by 3.
  const std::vector<Rgb>& face_colors;  // One per face.
  std::string caption;
};

// One entry of the legend row: a swatch of the colour and its label.
struct LegendEntry {
  Rgb color;
  std::string label;
};

enum class ViewCamera {
  // One camera for both views, fitted to the union of the two shapes' bounding boxes: the same
  // scale and the same place in either half, so that the right view is a translate of the left
  // one wherever the shapes agree (one mesh before and after an edit).
  shared,
  // Each view fitted to its own shape's bounding box (two different meshes).
  per_view,
};

struct SideBySideLayout {
  int width = 1600;  // The whole picture in pixels.
  int height = 800;
  std::string title;                // Empty: no title line (the views grow).
  std::vector<LegendEntry> legend;  // Empty: no legend row (the views grow).
  ViewCamera camera = ViewCamera::shared;
};

// The sizes every side-by-side picture accepts, in pixels.
inline constexpr int kMinPictureWidth = 320;
inline constexpr int kMinPictureHeight = 240;
inline constexpr int kMaxPictureSide = 16384;

// The picture as PNG bytes. Each view's faces are drawn where their projection covers a pixel's
// centre; edges are drawn in both views or in neither, as the left view's faces are large enough
// on screen to show them, so that the two look alike.
[[nodiscard]] std::string render_side_by_side_png(const PictureView& left, const PictureView& right,
                                                  const SideBySideLayout& layout);

// Where the parts of a side-by-side picture go, and the sizes of its texts.
struct SideBySideFrame {
  double margin = 0.0;
  double label_size = 0.0;  // Font sizes, pixels per em.
  double title_size = 0.0;
  double title_baseline = 0.0;
  PixelBox view;        // The left view; the right one lies `half_width` pixels further right.
  int half_width = 0;   // Whole pixels, so that both views fall on the pixel grid alike.
  double caption_baseline = 0.0;  // The captions, centred under the views.
  double legend_baseline = 0.0;
};

[[nodiscard]] SideBySideFrame side_by_side_frame(const SideBySideLayout& layout,
                                                 const TextRasterizer& font);

// Everything but the views: the title, the captions (left, right) under the views and the legend
// row, as render_side_by_side_png draws them.
void draw_side_by_side_texts(RgbImage& image, const SideBySideFrame& frame,
                             const SideBySideLayout& layout,
                             const std::array<std::string, 2>& captions,
                             const TextRasterizer& font);

// The camera of a view of its own shape (ViewCamera::per_view): looking along -z at the front of
// `positions` (#V by 3), y up, their bounding box centred in `view` and as large as it fits.
[[nodiscard]] OrthographicCamera front_camera(const Eigen::MatrixX3d& positions,
                                              const PixelBox& view);

// The checks before any work, each throwing Error naming `caller`:
// io_error unless `png` ends in .png (any case): these pictures are rasterized, never SVG.
void require_png(const std::filesystem::path& png, const std::string& caller);
// invalid_input for a width or height outside the sizes above.
void check_picture_size(int width, int height, const std::string& caller);
// invalid_input for a face naming a vertex below 0 or at `vertex_count` or above.
void check_face_corners(const Eigen::MatrixX3i& faces, Eigen::Index vertex_count,
                        const std::string& caller);
// invalid_input for a position that is not finite; `name` says which ("rest", "deformed", ...).
void check_finite_positions(const Eigen::MatrixX3d& positions, const std::string& name,
                            const std::string& caller);

}  // namespace harmonia::detail
