// Tangential Laplacian relaxation on the sphere (tangential_relaxation.h).

#include "sphere/tangential_relaxation.h"

#include <algorithm>

#include "sphere/sphere_orientation.h"

namespace harmonia::detail {
namespace {

// Faces around each vertex, in compressed rows.
struct VertexFaces {
  std::vector<int> offset, face;
};

VertexFaces vertex_faces(const Eigen::MatrixX3i& faces, int vertex_count) {
  VertexFaces incidence;
  incidence.offset.assign(static_cast<std::size_t>(vertex_count) + 1, 0);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k) ++incidence.offset[static_cast<std::size_t>(faces(f, k)) + 1];
  for (int v = 0; v < vertex_count; ++v)
    incidence.offset[static_cast<std::size_t>(v) + 1] += incidence.offset[static_cast<std::size_t>(v)];
  incidence.face.resize(static_cast<std::size_t>(incidence.offset.back()));
  std::vector<int> next(incidence.offset.begin(), incidence.offset.end() - 1);
  for (Eigen::Index f = 0; f < faces.rows(); ++f)
    for (int k = 0; k < 3; ++k)
      incidence.face[static_cast<std::size_t>(next[static_cast<std::size_t>(faces(f, k))]++)] = static_cast<int>(f);
  return incidence;
}

int orientation(const Eigen::MatrixX3d& points, const Eigen::MatrixX3i& faces, int f) {
  return sphere_orientation_sign(points.row(faces(f, 0)).transpose(),
                                 points.row(faces(f, 1)).transpose(),
                                 points.row(faces(f, 2)).transpose());
}

}  // namespace

std::vector<char> vertices_within_rings(const Eigen::MatrixX3i& faces, int vertex_count,
                                        const std::vector<int>& seeds, int rings) {
  std::vector<char> inside(static_cast<std::size_t>(vertex_count), 0);
  for (const int seed : seeds) inside[static_cast<std::size_t>(seed)] = 1;
  for (int ring = 0; ring < rings; ++ring) {
    std::vector<char> grown = inside;
    for (Eigen::Index f = 0; f < faces.rows(); ++f) {
      const bool touches = inside[static_cast<std::size_t>(faces(f, 0))] ||
                           inside[static_cast<std::size_t>(faces(f, 1))] ||
                           inside[static_cast<std::size_t>(faces(f, 2))];
      if (!touches) continue;
      for (int k = 0; k < 3; ++k) grown[static_cast<std::size_t>(faces(f, k))] = 1;
    }
    inside = std::move(grown);
  }
  return inside;
}

RelaxationOutcome relax_on_sphere(const Eigen::SparseMatrix<double>& weights,
                                  const Eigen::MatrixX3i& faces, const std::vector<char>& movable,
                                  int steps, bool keep_valid, Eigen::MatrixX3d& points) {
  const auto vertex_count = static_cast<int>(points.rows());
  const VertexFaces incidence = vertex_faces(faces, vertex_count);
  // Rows of the weights: the laplacian.h convention stores -w_ij off the diagonal. A column-major
  // matrix is read through its transpose's columns.
  const Eigen::SparseMatrix<double, Eigen::RowMajor> rows = weights;
  RelaxationOutcome outcome;
  std::vector<char> moved(static_cast<std::size_t>(vertex_count), 0);
  for (int step = 0; step < steps; ++step) {
    Eigen::MatrixX3d next = points;
    for (int v = 0; v < vertex_count; ++v) {
      if (!movable[static_cast<std::size_t>(v)]) continue;
      Eigen::Vector3d average = Eigen::Vector3d::Zero();
      double total = 0.0;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator entry(rows, v); entry; ++entry) {
        if (entry.col() == v) continue;
        const double w = -entry.value();
        average += w * points.row(entry.col()).transpose();
        total += w;
      }
      if (!(total > 0.0)) continue;
      const Eigen::Vector3d x = points.row(v).transpose();
      const Eigen::Vector3d laplacian = average / total - x;
      const Eigen::Vector3d moved_to = x + laplacian - laplacian.dot(x) * x;
      next.row(v) = moved_to.normalized().transpose();
    }
    if (keep_valid) {
      // Undo the moves of the vertices of every triangle the step turned over, until none is.
      std::vector<int> suspects;
      for (int v = 0; v < vertex_count; ++v)
        if (movable[static_cast<std::size_t>(v)]) suspects.push_back(v);
      while (!suspects.empty()) {
        std::vector<int> undo;
        for (const int v : suspects) {
          for (int slot = incidence.offset[static_cast<std::size_t>(v)];
               slot < incidence.offset[static_cast<std::size_t>(v) + 1]; ++slot) {
            const int f = incidence.face[static_cast<std::size_t>(slot)];
            if (orientation(next, faces, f) > 0 || orientation(points, faces, f) <= 0) continue;
            for (int k = 0; k < 3; ++k)
              if (next.row(faces(f, k)) != points.row(faces(f, k))) undo.push_back(faces(f, k));
          }
        }
        std::sort(undo.begin(), undo.end());
        undo.erase(std::unique(undo.begin(), undo.end()), undo.end());
        for (const int v : undo) next.row(v) = points.row(v);
        outcome.held_back += static_cast<int>(undo.size());
        // Only the neighbourhoods of the undone vertices can still hold a turned triangle.
        suspects.clear();
        for (const int v : undo)
          for (int slot = incidence.offset[static_cast<std::size_t>(v)];
               slot < incidence.offset[static_cast<std::size_t>(v) + 1]; ++slot)
            for (int k = 0; k < 3; ++k)
              suspects.push_back(faces(incidence.face[static_cast<std::size_t>(slot)], k));
        std::sort(suspects.begin(), suspects.end());
        suspects.erase(std::unique(suspects.begin(), suspects.end()), suspects.end());
      }
    }
    for (int v = 0; v < vertex_count; ++v)
      if (next.row(v) != points.row(v)) moved[static_cast<std::size_t>(v)] = 1;
    points = std::move(next);
  }
  outcome.moved_vertices = static_cast<int>(std::count(moved.begin(), moved.end(), 1));
  return outcome;
}

}  // namespace harmonia::detail
