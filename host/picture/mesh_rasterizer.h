#pragma once
// Internal: the software rasterizer of the pictures that show a surface in 3D (sphere_picture.cpp,
// side_by_side_picture.cpp): an orthographic camera, a depth buffer that also keeps which face is
// seen at each pixel, flat Lambert shading, and the painting of the faces seen with their edges.
// Faces are drawn in the order given and ties keep the earlier face, so the same calls give the
// same pixels.

#include <Eigen/Core>
#include <array>
#include <cstddef>
#include <vector>

#include "picture/color_map.h"
#include "picture/pixel_box.h"
#include "picture/raster_image.h"

namespace harmonia::detail {

// An orthographic view: the viewer far out along `toward`, `up` pointing up the picture, `target`
// drawn at pixel `centre`, `scale` pixels per unit of length.
struct OrthographicCamera {
  Eigen::Vector3d toward = Eigen::Vector3d::UnitZ();  // Unit; from the scene towards the viewer.
  Eigen::Vector3d up = Eigen::Vector3d::UnitY();      // Unit, perpendicular to `toward`.
  Eigen::Vector3d right = Eigen::Vector3d::UnitX();   // up x toward.
  Eigen::Vector3d target = Eigen::Vector3d::Zero();
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();  // Pixels (x right, y down).
  double scale = 1.0;

  [[nodiscard]] Eigen::Vector2d pixel(const Eigen::Vector3d& point) const {
    const Eigen::Vector3d offset = point - target;
    return centre + scale * Eigen::Vector2d(offset.dot(right), -offset.dot(up));
  }
  // Larger is nearer the viewer.
  [[nodiscard]] double depth(const Eigen::Vector3d& point) const {
    return (point - target).dot(toward);
  }
};

// Per pixel of a box of the picture: the depth of the nearest face drawn there and its index.
class DepthBuffer {
 public:
  // Covers the pixels of `area` (with a pixel to spare on each side for rounding) that lie in an
  // image_width x image_height picture. The camera must outlive the buffer.
  DepthBuffer(const OrthographicCamera& camera, const PixelBox& area, int image_width,
              int image_height);

  // Draws face `face` (its three corners) where its projection covers a pixel's centre and lies
  // nearer than what is there; `depth_bias` pulls it towards the viewer. Ties keep the earlier
  // face.
  void rasterize(int face, const std::array<Eigen::Vector3d, 3>& corners, double depth_bias = 0.0);

  [[nodiscard]] const OrthographicCamera& camera() const { return camera_; }
  // The buffer's box in picture pixels; cell (x, y) is pixel (left() + x, top() + y).
  [[nodiscard]] int left() const { return left_; }
  [[nodiscard]] int top() const { return top_; }
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }
  // The face seen at cell (x, y), -1 for none (also outside the buffer).
  [[nodiscard]] int face(int x, int y) const {
    return x < 0 || y < 0 || x >= width_ || y >= height_ ? -1 : face_[index(x, y)];
  }
  // The depth seen at cell (x, y), which must lie in the buffer; -infinity where no face is.
  [[nodiscard]] double depth(int x, int y) const { return depth_[index(x, y)]; }

 private:
  [[nodiscard]] std::size_t index(int x, int y) const {
    return static_cast<std::size_t>(y) * static_cast<std::size_t>(width_) +
           static_cast<std::size_t>(x);
  }

  const OrthographicCamera& camera_;
  int left_ = 0, top_ = 0, width_ = 0, height_ = 0;
  std::vector<double> depth_;
  std::vector<int> face_;
};

// `color` lit from the front, a little above and left of the viewer (flat Lambert: ambient plus
// diffuse light). Either side of a face is lit alike, so open surfaces seen from behind and faces
// turned over stay readable; a zero normal counts as facing the light.
[[nodiscard]] Rgb flat_shaded(const Rgb& color, const Eigen::Vector3d& normal,
                              const OrthographicCamera& camera);

// Whether the faces seen in `buffer` (of `face_count` faces) are large enough on screen, on
// average, for their edges to show without covering their colours.
[[nodiscard]] bool edges_fit(const DepthBuffer& buffer, std::size_t face_count);

// Sets every pixel of the buffer where a face is seen to that face's colour (`face_colors` has
// one per face). The pixels are moved by `offset` (whole pixels), here and in blend_seen_edges:
// views rasterized with the same camera and painted at different places come out identical
// wherever their faces are.
void paint_seen_faces(RgbImage& image, const DepthBuffer& buffer,
                      const std::vector<Rgb>& face_colors,
                      const Eigen::Vector2i& offset = Eigen::Vector2i::Zero());

// Blends the edges between the faces seen lightly into the picture, except around the faces with
// `without_edges` set (empty: none).
void blend_seen_edges(RgbImage& image, const DepthBuffer& buffer,
                      const std::vector<char>& without_edges = {},
                      const Eigen::Vector2i& offset = Eigen::Vector2i::Zero());

}  // namespace harmonia::detail
