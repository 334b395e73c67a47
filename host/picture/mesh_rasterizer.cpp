// The depth-buffered rasterizer of the 3D pictures: edge functions evaluated at pixel centres,
// depth interpolated linearly (exact for an orthographic projection).
#include "picture/mesh_rasterizer.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

namespace harmonia::detail {
namespace {

// Enough diffuse light to show a surface's shape, enough ambient light to keep its colours
// readable where it turns away.
constexpr double kAmbient = 0.6;
constexpr double kDiffuse = 0.4;
// Below this mean size of the faces seen (pixels) edges would cover the colours; they are left out.
constexpr double kEdgeMinimumPixels = 40.0;
// Edges are blended in lightly (of 255), so that they outline faces without darkening them.
constexpr int kEdgeCoverage = 72;

// Twice the signed area of triangle (a, b, p); positive when p lies left of a -> b in the picture.
double edge_function(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                     const Eigen::Vector2d& p) {
  return (b.x() - a.x()) * (p.y() - a.y()) - (b.y() - a.y()) * (p.x() - a.x());
}

}  // namespace

DepthBuffer::DepthBuffer(const OrthographicCamera& camera, const PixelBox& area, int image_width,
                         int image_height)
    : camera_(camera) {
  left_ = std::max(0, static_cast<int>(std::floor(area.left)) - 1);
  top_ = std::max(0, static_cast<int>(std::floor(area.top)) - 1);
  const int right = std::min(image_width, static_cast<int>(std::ceil(area.right)) + 2);
  const int bottom = std::min(image_height, static_cast<int>(std::ceil(area.bottom)) + 2);
  width_ = std::max(0, right - left_);
  height_ = std::max(0, bottom - top_);
  const auto cells = static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_);
  depth_.assign(cells, -std::numeric_limits<double>::infinity());
  face_.assign(cells, -1);
}

void DepthBuffer::rasterize(int face, const std::array<Eigen::Vector3d, 3>& corners,
                            double depth_bias) {
  std::array<Eigen::Vector2d, 3> at;
  std::array<double, 3> depth;
  for (int k = 0; k < 3; ++k) {
    at[k] = camera_.pixel(corners[k]);
    depth[k] = camera_.depth(corners[k]) + depth_bias;
  }
  double twice_area = edge_function(at[0], at[1], at[2]);
  if (twice_area == 0.0) return;  // Seen edge-on: no interior.
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
      const double w0 = edge_function(at[1], at[2], centre);
      const double w1 = edge_function(at[2], at[0], centre);
      const double w2 = edge_function(at[0], at[1], centre);
      if (w0 < 0.0 || w1 < 0.0 || w2 < 0.0) continue;
      const double z = (w0 * depth[0] + w1 * depth[1] + w2 * depth[2]) / twice_area;
      const std::size_t cell = index(x, y);
      if (z > depth_[cell]) {
        depth_[cell] = z;
        face_[cell] = face;
      }
    }
  }
}

Rgb flat_shaded(const Rgb& color, const Eigen::Vector3d& normal,
                const OrthographicCamera& camera) {
  const Eigen::Vector3d light =
      (camera.toward + 0.3 * camera.up - 0.25 * camera.right).normalized();
  const double cosine = normal.norm() > 0.0 ? std::abs(normal.normalized().dot(light)) : 1.0;
  const double factor = kAmbient + kDiffuse * cosine;
  const auto channel = [factor](std::uint8_t value) {
    return static_cast<std::uint8_t>(std::lround(std::clamp(value * factor, 0.0, 255.0)));
  };
  return {channel(color.red), channel(color.green), channel(color.blue)};
}

bool edges_fit(const DepthBuffer& buffer, std::size_t face_count) {
  std::size_t covered = 0;
  std::vector<char> seen(face_count, 0);
  for (int y = 0; y < buffer.height(); ++y) {
    for (int x = 0; x < buffer.width(); ++x) {
      const int f = buffer.face(x, y);
      if (f < 0) continue;
      ++covered;
      seen[static_cast<std::size_t>(f)] = 1;
    }
  }
  const auto seen_faces = static_cast<std::size_t>(std::count(seen.begin(), seen.end(), 1));
  return seen_faces > 0 && static_cast<double>(covered) / seen_faces >= kEdgeMinimumPixels;
}

void paint_seen_faces(RgbImage& image, const DepthBuffer& buffer,
                      const std::vector<Rgb>& face_colors, const Eigen::Vector2i& offset) {
  const int left = buffer.left() + offset.x(), top = buffer.top() + offset.y();
  for (int y = 0; y < buffer.height(); ++y) {
    for (int x = 0; x < buffer.width(); ++x) {
      const int f = buffer.face(x, y);
      if (f >= 0) image.set(left + x, top + y, face_colors[static_cast<std::size_t>(f)]);
    }
  }
}

void blend_seen_edges(RgbImage& image, const DepthBuffer& buffer,
                      const std::vector<char>& without_edges, const Eigen::Vector2i& offset) {
  const int left = buffer.left() + offset.x(), top = buffer.top() + offset.y();
  for (int y = 0; y < buffer.height(); ++y) {
    for (int x = 0; x < buffer.width(); ++x) {
      const int f = buffer.face(x, y);
      if (f < 0 || (!without_edges.empty() && without_edges[static_cast<std::size_t>(f)])) continue;
      // A pixel whose right or lower neighbour shows another face lies on an edge.
      if (buffer.face(x + 1, y) != f || buffer.face(x, y + 1) != f)
        image.blend(left + x, top + y, kEdgeColor, kEdgeCoverage);
    }
  }
}

}  // namespace harmonia::detail
