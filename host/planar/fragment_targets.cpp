// The fragmented mesh of the free-boundary maps: per-triangle stretches of a layout, the rotation
// field that glues the fragments, and the fragments themselves (fragment_targets.h).

#include "planar/fragment_targets.h"

#include <cmath>
#include <future>
#include <utility>

#include <Eigen/Dense>

#include "harmonia/quasi_harmonic_operator.h"
#include "mesh/edge_table.h"
#include "operators/element_stiffness.h"
#include "mesh/helper_tasks.h"

namespace harmonia::detail {
namespace {

Eigen::Matrix2d rotation(double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  Eigen::Matrix2d r;
  r << c, -s, s, c;
  return r;
}

// R(angle) diag(first, second) R(angle)^T.
Eigen::Matrix2d symmetric_from_eigen(double angle, double first, double second) {
  const Eigen::Matrix2d r = rotation(angle);
  return r * Eigen::Vector2d(first, second).asDiagonal() * r.transpose();
}

// Runs work(begin, end) on [0, count / 2) here and [count / 2, count) on a second thread: for
// loops whose iterations write disjoint slots (the result does not depend on the timing).
template <typename Work>
void in_two_halves(Eigen::Index count, const Work& work) {
  const Eigen::Index middle = count / 2;
  std::future<void> second = start_beside([&] { work(middle, count); });
  work(0, middle);
  second.get();
}

}  // namespace

Eigen::Matrix2d TriangleStretches::power(Eigen::Index face, double step) const {
  if (step == 0.0) return Eigen::Matrix2d::Identity();
  return symmetric_from_eigen(angle[face], std::pow(major[face], step), std::pow(minor[face], step));
}

std::vector<Eigen::Matrix2d> TriangleStretches::powers(double step) const {
  std::vector<Eigen::Matrix2d> shapes(static_cast<std::size_t>(angle.size()));
  in_two_halves(angle.size(), [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index f = begin; f < end; ++f) shapes[static_cast<std::size_t>(f)] = power(f, step);
  });
  return shapes;
}

Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> TriangleStretches::conductances(
    double step) const {
  Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor> tensors(angle.size(), 4);
  for (Eigen::Index f = 0; f < angle.size(); ++f) {
    const Eigen::Matrix2d c =
        symmetric_from_eigen(angle[f], std::pow(major[f], -step), std::pow(minor[f], -step));
    tensors.row(f) << c(0, 0), c(0, 1), c(1, 0), c(1, 1);
  }
  return tensors;
}

TriangleStretches triangle_stretches(const Mesh& mesh, const Eigen::MatrixX2d& uv) {
  const Eigen::Index face_count = mesh.faces.rows();
  TriangleStretches stretches;
  stretches.angle = Eigen::VectorXd::Zero(face_count);
  stretches.major = Eigen::VectorXd::Ones(face_count);
  stretches.minor = Eigen::VectorXd::Ones(face_count);
  // I = J^T J (5.2) of every face, infinite where the uv triangle has no area (no Jacobian: K
  // stays the identity); K = sqrt(I) shares I's eigenvectors, with the square roots of its
  // eigenvalues (5.5).
  const TriangleTensors forms = first_fundamental_forms(mesh, uv);
  for (Eigen::Index f = 0; f < face_count; ++f) {
    if (!forms.row(f).allFinite()) continue;
    const double half_trace = 0.5 * (forms(f, 0) + forms(f, 3));
    const double half_difference = 0.5 * (forms(f, 0) - forms(f, 3));
    const double radius = std::hypot(half_difference, forms(f, 1));
    const double larger = half_trace + radius, smaller = half_trace - radius;
    if (!(smaller > 0.0) || !std::isfinite(larger)) continue;  // degenerate 3D triangle
    stretches.angle[f] = 0.5 * std::atan2(2.0 * forms(f, 1), forms(f, 0) - forms(f, 3));
    stretches.major[f] = std::sqrt(larger);
    stretches.minor[f] = std::sqrt(smaller);
  }
  return stretches;
}

FragmentRotationField::FragmentRotationField(const Mesh& mesh) : mesh_(mesh) {
  const EdgeTable edges(mesh);
  const auto face_count = static_cast<int>(mesh.faces.rows());
  // Faces' interior edges as adjacency lists (CSR), for the spanning tree.
  std::vector<int> degree(static_cast<std::size_t>(face_count) + 1, 0);
  for (int e = 0; e < edges.size(); ++e) {
    if (edges.face_count(e) != 2) continue;
    const auto uses = edges.uses(e);
    first_face_.push_back(uses[0].face());
    second_face_.push_back(uses[1].face());
    edge_from_.push_back(mesh.faces(uses[0].face(), uses[0].corner()));
    edge_to_.push_back(mesh.faces(uses[0].face(), (uses[0].corner() + 1) % 3));
    ++degree[static_cast<std::size_t>(uses[0].face()) + 1];
    ++degree[static_cast<std::size_t>(uses[1].face()) + 1];
  }
  for (int f = 0; f < face_count; ++f) degree[static_cast<std::size_t>(f) + 1] += degree[static_cast<std::size_t>(f)];
  std::vector<int> incident(static_cast<std::size_t>(degree.back()));
  std::vector<int> filled(degree.begin(), degree.end() - 1);
  for (std::size_t e = 0; e < first_face_.size(); ++e) {
    incident[static_cast<std::size_t>(filled[static_cast<std::size_t>(first_face_[e])]++)] = static_cast<int>(e);
    incident[static_cast<std::size_t>(filled[static_cast<std::size_t>(second_face_[e])]++)] = static_cast<int>(e);
  }
  // Breadth-first from face 0 (a disk's faces are connected through interior edges).
  std::vector<char> reached(static_cast<std::size_t>(face_count), 0);
  if (face_count > 0) {
    reached[0] = 1;
    tree_face_.push_back(0);
    tree_edge_.push_back(-1);
  }
  for (std::size_t next = 0; next < tree_face_.size(); ++next) {
    const int f = tree_face_[next];
    for (int slot = degree[static_cast<std::size_t>(f)]; slot < degree[static_cast<std::size_t>(f) + 1]; ++slot) {
      const int e = incident[static_cast<std::size_t>(slot)];
      const int other = first_face_[static_cast<std::size_t>(e)] == f ? second_face_[static_cast<std::size_t>(e)]
                                                                     : first_face_[static_cast<std::size_t>(e)];
      if (reached[static_cast<std::size_t>(other)]) continue;
      reached[static_cast<std::size_t>(other)] = 1;
      tree_face_.push_back(other);
      tree_edge_.push_back(e);
    }
  }
}

void FragmentRotationField::set_cotangent_weights(
    const Eigen::SparseMatrix<double>& cotangent_laplacian) {
  cotangent_weight_.resize(first_face_.size());
  for (std::size_t e = 0; e < first_face_.size(); ++e)
    cotangent_weight_[e] = -cotangent_laplacian.coeff(edge_from_[e], edge_to_[e]);
}

bool FragmentRotationField::solve(const Eigen::MatrixX2d& uv,
                                  const std::vector<Eigen::Matrix2d>& shapes,
                                  DirichletSystem& boundary_system, Eigen::VectorXd& theta,
                                  SolveReport& report) {
  // delta_e, and the circulation around each vertex: crossing the edge a -> b counter-clockwise
  // around a adds theta_first - theta_second, around b subtracts it. Column 1 stays zero (the
  // system solves two columns at once).
  const std::size_t edge_count = first_face_.size();
  std::vector<double> delta(edge_count);
  Eigen::MatrixX2d circulation = Eigen::MatrixX2d::Zero(mesh_.vertices.rows(), 2);
  in_two_halves(static_cast<Eigen::Index>(edge_count), [&](Eigen::Index begin, Eigen::Index end) {
    for (auto e = static_cast<std::size_t>(begin); e < static_cast<std::size_t>(end); ++e) {
      const Eigen::Vector2d edge = (uv.row(edge_to_[e]) - uv.row(edge_from_[e])).transpose();
      const Eigen::Vector2d as_first = shapes[static_cast<std::size_t>(first_face_[e])] * edge;
      const Eigen::Vector2d as_second = shapes[static_cast<std::size_t>(second_face_[e])] * edge;
      // theta_f - theta_g = arg(K_g e) - arg(K_f e): the angle from as_first to as_second.
      delta[e] = std::atan2(as_first.x() * as_second.y() - as_first.y() * as_second.x(),
                            as_first.dot(as_second));
    }
  });
  for (std::size_t e = 0; e < edge_count; ++e) {
    circulation(edge_from_[e], 0) += delta[e];
    circulation(edge_to_[e], 0) -= delta[e];
  }
  Eigen::MatrixX2d potential;
  if (!boundary_system.solve(
          Eigen::MatrixX2d::Zero(mesh_.vertices.rows() - boundary_system.free_count(), 2),
          circulation, potential, report))
    return false;
  // What is left has no circulation: sum it along the tree.
  theta = Eigen::VectorXd::Zero(mesh_.faces.rows());
  for (std::size_t k = 1; k < tree_face_.size(); ++k) {
    const auto e = static_cast<std::size_t>(tree_edge_[k]);
    const double exact =
        delta[e] - cotangent_weight_[e] * (potential(edge_from_[e], 0) - potential(edge_to_[e], 0));
    const int f = first_face_[e], g = second_face_[e];
    if (tree_face_[k] == g) theta[g] = theta[f] - exact; else theta[f] = theta[g] + exact;
  }
  return true;
}

PairStiffness tensor_pair_stiffness(
    const Mesh& mesh, const Eigen::MatrixX2d& uv,
    const Eigen::Matrix<double, Eigen::Dynamic, 4, Eigen::RowMajor>& tensors) {
  PairStiffness stiffness(mesh.faces.rows(), 3);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    Eigen::Matrix2d tensor;
    tensor << tensors(f, 0), tensors(f, 1), tensors(f, 2), tensors(f, 3);
    stiffness.row(f) = tensor_cotangent_pair_stiffness(uv, mesh.faces.row(f), tensor).transpose();
  }
  return stiffness;
}

Eigen::MatrixXd fragment_corners(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                                 const std::vector<Eigen::Matrix2d>& shapes,
                                 const Eigen::VectorXd& theta) {
  Eigen::MatrixXd corners(3 * mesh.faces.rows(), 2);
  in_two_halves(mesh.faces.rows(), [&](Eigen::Index begin, Eigen::Index end) {
    for (Eigen::Index f = begin; f < end; ++f) {
      Eigen::Matrix2d shape = shapes[static_cast<std::size_t>(f)];
      if (theta.size() > 0) shape = rotation(theta[f]) * shape;
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d corner = shape * uv.row(mesh.faces(f, k)).transpose();
        corners.row(3 * f + k) = corner.transpose();
      }
    }
  });
  return corners;
}

}  // namespace harmonia::detail
