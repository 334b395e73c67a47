// Gradients of piecewise-linear (P1) functions, the divergence back to the vertices, and the
// Poisson right-hand side of a fragmented target (thesis 6.2.2). Everything is computed per triangle
// from the corner positions; the hat function of corner k has the constant gradient
// n x e_k / |n|^2 in 3D (n = (p1 - p0) x (p2 - p0), e_k the edge opposite corner k, oriented with the
// face), which in 2D is e_k rotated by +90 degrees over twice the signed area (4.38-4.39).

#include "harmonia/gradient.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <initializer_list>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "harmonia/laplacian.h"
#include "harmonia/types.h"
#include "mesh/adjacency_pattern.h"
#include "mesh/power_of_two_scale.h"

namespace harmonia {
namespace {

int checked_dimension(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces, const char* who) {
  if (positions.cols() != 2 && positions.cols() != 3) {
    throw Error(Status::invalid_input, std::string(who) + ": positions must have 2 or 3 columns, got " +
                                           std::to_string(positions.cols()));
  }
  detail::check_face_indices(faces, positions.rows(), who);
  return static_cast<int>(positions.cols());
}

Eigen::Vector3d corner(const Eigen::MatrixXd& positions, int vertex) {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  point.head(positions.cols()) = positions.row(vertex).transpose();
  return point;
}

// Hat-function gradients of the three corners of face f (as 3-vectors; z = 0 for planar input) and
// the unsigned area. A zero-area face gets zero gradients.
struct FaceGradients {
  std::array<Eigen::Vector3d, 3> hat;
  double area = 0.0;
};

// The power of two that brings a face's edge vectors into the safe range (1 inside it), so that
// their squares and cross products neither underflow (a model in units of 1e-100) nor overflow
// (1e200); the hat gradients, which go as 1/length, and the area, as length^2, come back exactly.
double face_scale(std::initializer_list<const Eigen::Vector3d*> edges) {
  double largest = 0.0;
  for (const Eigen::Vector3d* edge : edges) largest = std::max(largest, edge->cwiseAbs().maxCoeff());
  return detail::safe_range_scale_for(largest);
}

FaceGradients face_gradients(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces,
                             Eigen::Index f) {
  const std::array<Eigen::Vector3d, 3> p = {corner(positions, faces(f, 0)), corner(positions, faces(f, 1)),
                                            corner(positions, faces(f, 2))};
  Eigen::Vector3d first_leg = p[1] - p[0], second_leg = p[2] - p[0];
  std::array<Eigen::Vector3d, 3> opposite_edge;
  for (int k = 0; k < 3; ++k) opposite_edge[k] = p[(k + 2) % 3] - p[(k + 1) % 3];
  const double scale =
      face_scale({&first_leg, &second_leg, &opposite_edge[0], &opposite_edge[1], &opposite_edge[2]});
  if (scale != 1.0) {
    first_leg *= scale;
    second_leg *= scale;
    for (Eigen::Vector3d& edge : opposite_edge) edge *= scale;
  }
  const Eigen::Vector3d normal = first_leg.cross(second_leg);  // length = twice the area
  const double normal_squared = normal.squaredNorm();
  FaceGradients result;
  result.area = 0.5 * std::sqrt(normal_squared);
  if (scale != 1.0) result.area = result.area / scale / scale;
  for (int k = 0; k < 3; ++k) {
    result.hat[k] = normal_squared > 0.0
                        ? Eigen::Vector3d(normal.cross(opposite_edge[k]) / normal_squared)
                        : Eigen::Vector3d::Zero();
    if (scale != 1.0) result.hat[k] *= scale;
  }
  return result;
}

}  // namespace

Eigen::VectorXd triangle_areas(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces) {
  checked_dimension(positions, faces, "triangle_areas");
  Eigen::VectorXd areas(faces.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d a = corner(positions, faces(f, 0));
    Eigen::Vector3d first_leg = corner(positions, faces(f, 1)) - a;
    Eigen::Vector3d second_leg = corner(positions, faces(f, 2)) - a;
    const Eigen::Vector3d third_leg = corner(positions, faces(f, 2)) - corner(positions, faces(f, 1));
    const double scale = face_scale({&first_leg, &second_leg, &third_leg});
    if (scale == 1.0) {
      areas[f] = 0.5 * first_leg.cross(second_leg).norm();
    } else {
      areas[f] = 0.5 * (first_leg * scale).cross(second_leg * scale).norm() / scale / scale;
    }
  }
  return areas;
}

Eigen::SparseMatrix<double> gradient_operator(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces) {
  const int dimension = checked_dimension(positions, faces, "gradient_operator");
  // Row-major compressed arrays with (at most) three entries per row, one per corner, sorted by
  // column; a face with a repeated index merges its entries. Then one conversion to column-major.
  const Eigen::Index row_count = dimension * faces.rows();
  std::vector<int> row_starts(static_cast<std::size_t>(row_count) + 1, 0);
  std::vector<int> columns;
  std::vector<double> values;
  columns.reserve(static_cast<std::size_t>(3 * row_count));
  values.reserve(static_cast<std::size_t>(3 * row_count));
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const FaceGradients gradients = face_gradients(positions, faces, f);
    std::array<int, 3> order = {0, 1, 2};
    std::sort(order.begin(), order.end(), [&](int a, int b) { return faces(f, a) < faces(f, b); });
    for (int axis = 0; axis < dimension; ++axis) {
      for (int slot = 0; slot < 3; ++slot) {
        const int k = order[static_cast<std::size_t>(slot)];
        if (slot > 0 && faces(f, k) == columns.back()) {
          values.back() += gradients.hat[k][axis];
        } else {
          columns.push_back(faces(f, k));
          values.push_back(gradients.hat[k][axis]);
        }
      }
      row_starts[static_cast<std::size_t>(dimension * f + axis) + 1] = static_cast<int>(columns.size());
    }
  }
  const Eigen::Map<const Eigen::SparseMatrix<double, Eigen::RowMajor>> rows(
      row_count, positions.rows(), static_cast<Eigen::Index>(columns.size()), row_starts.data(),
      columns.data(), values.data());
  return Eigen::SparseMatrix<double>(rows);
}

Eigen::VectorXd divergence(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces,
                           const Eigen::VectorXd& field) {
  const int dimension = checked_dimension(positions, faces, "divergence");
  if (field.size() != dimension * faces.rows()) {
    throw Error(Status::invalid_input, "divergence: field has " + std::to_string(field.size()) +
                                           " entries, expected " +
                                           std::to_string(dimension * faces.rows()));
  }
  // G^T diag(area) F: each face hands area * (grad phi_k . F_f) to its corner k.
  Eigen::VectorXd result = Eigen::VectorXd::Zero(positions.rows());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const FaceGradients gradients = face_gradients(positions, faces, f);
    Eigen::Vector3d vector = Eigen::Vector3d::Zero();
    vector.head(dimension) = field.segment(dimension * f, dimension);
    for (int k = 0; k < 3; ++k) result[faces(f, k)] += gradients.area * gradients.hat[k].dot(vector);
  }
  return result;
}

Eigen::MatrixXd fragment_poisson_rhs(const Eigen::MatrixXd& positions, const Eigen::MatrixX3i& faces,
                                     const Eigen::MatrixXd& fragments) {
  checked_dimension(positions, faces, "fragment_poisson_rhs");
  if (fragments.rows() != 3 * faces.rows()) {
    throw Error(Status::invalid_input, "fragment_poisson_rhs: fragments has " +
                                           std::to_string(fragments.rows()) + " rows, expected 3 * " +
                                           std::to_string(faces.rows()) + " faces");
  }
  // Each face's cotangent stiffness S (4.41; S_ab = -cot(theta_c)/2 off the diagonal, rows summing
  // to zero) applied to the face's own corner coordinates, gathered at the shared vertices.
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(positions.rows(), fragments.cols());
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    const Eigen::Vector3d half_cot = cotangent_half_weights(
        corner(positions, faces(f, 0)), corner(positions, faces(f, 1)), corner(positions, faces(f, 2)));
    for (int k = 0; k < 3; ++k) {
      // Edge (a, b) opposite corner k carries weight half_cot[k]: it adds w (x_a - x_b) to row a.
      const int a = (k + 1) % 3, b = (k + 2) % 3;
      const Eigen::RowVectorXd difference = fragments.row(3 * f + a) - fragments.row(3 * f + b);
      rhs.row(faces(f, a)) += half_cot[k] * difference;
      rhs.row(faces(f, b)) -= half_cot[k] * difference;
    }
  }
  return rhs;
}

}  // namespace harmonia
