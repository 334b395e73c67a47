#pragma once
// Collects vertices and triangles while a file is parsed (flat, growable arrays) and turns them
// into a Mesh at the end. Polygons are split into triangle fans (v0, vk, vk+1). Validation with
// good messages is the reader's job, because only the reader knows the line or byte to name.

#include <cstddef>
#include <span>
#include <vector>

#include "harmonia/mesh.h"

namespace harmonia::detail {

class MeshBuilder {
 public:
  void reserve(std::size_t vertices, std::size_t triangles) {
    coordinates_.reserve(3 * vertices);
    corners_.reserve(3 * triangles);
  }

  void add_vertex(double x, double y, double z) {
    coordinates_.push_back(x);
    coordinates_.push_back(y);
    coordinates_.push_back(z);
  }
  void add_triangle(int a, int b, int c) {
    corners_.push_back(a);
    corners_.push_back(b);
    corners_.push_back(c);
  }
  //! Adds the fan triangulation of a polygon with at least 3 corners.
  void add_polygon(std::span<const int> corners) {
    for (std::size_t k = 1; k + 1 < corners.size(); ++k) {
      add_triangle(corners[0], corners[k], corners[k + 1]);
    }
  }

  [[nodiscard]] int vertex_count() const { return static_cast<int>(coordinates_.size() / 3); }
  [[nodiscard]] std::size_t triangle_count() const { return corners_.size() / 3; }

  //! Moves the collected arrays into a Mesh (vertex and face order as added).
  [[nodiscard]] Mesh build() const;

 private:
  std::vector<double> coordinates_;  // x0 y0 z0 x1 y1 z1 ...
  std::vector<int> corners_;         // a0 b0 c0 a1 b1 c1 ...
};

//! #rows by `Columns` Eigen matrix from a flat row-major array (used for vertices, faces and uv).
template <typename Matrix, typename Scalar>
Matrix matrix_from_rows(const std::vector<Scalar>& flat) {
  constexpr int columns = Matrix::ColsAtCompileTime;
  using RowMajor = Eigen::Matrix<Scalar, Eigen::Dynamic, columns, Eigen::RowMajor>;
  const auto rows = static_cast<Eigen::Index>(flat.size() / columns);
  return Eigen::Map<const RowMajor>(flat.data(), rows, columns);
}

}  // namespace harmonia::detail
