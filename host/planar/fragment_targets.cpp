// The fragmented mesh of the free-boundary maps: per-triangle stretches of a layout, the rotation
// field that glues the fragments, and the fragments themselves (fragment_targets.h).

#include "planar/fragment_targets.h"

#include <cmath>
#include <utility>

#include <Eigen/Dense>

#include "mesh/edge_table.h"

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

}  // namespace

Eigen::Matrix2d TriangleStretches::power(Eigen::Index face, double step) const {
  if (step == 0.0) return Eigen::Matrix2d::Identity();
  return symmetric_from_eigen(angle[face], std::pow(major[face], step), std::pow(minor[face], step));
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
  for (Eigen::Index f = 0; f < face_count; ++f) {
    const int i = mesh.faces(f, 0), j = mesh.faces(f, 1), k = mesh.faces(f, 2);
    Eigen::Matrix<double, 3, 2> edges3d;
    edges3d.col(0) = (mesh.vertices.row(j) - mesh.vertices.row(i)).transpose();
    edges3d.col(1) = (mesh.vertices.row(k) - mesh.vertices.row(i)).transpose();
    Eigen::Matrix2d edges_uv;
    edges_uv.col(0) = (uv.row(j) - uv.row(i)).transpose();
    edges_uv.col(1) = (uv.row(k) - uv.row(i)).transpose();
    if (edges_uv.determinant() == 0.0) continue;  // no Jacobian: identity
    // dX = J dU (5.1) and I = J^T J (5.2); K = sqrt(I) shares I's eigenvectors, with the square
    // roots of its eigenvalues (5.5).
    const Eigen::Matrix<double, 3, 2> jacobian = edges3d * edges_uv.inverse();
    const Eigen::Matrix2d form = jacobian.transpose() * jacobian;
    const double half_trace = 0.5 * (form(0, 0) + form(1, 1));
    const double half_difference = 0.5 * (form(0, 0) - form(1, 1));
    const double radius = std::hypot(half_difference, form(0, 1));
    const double larger = half_trace + radius, smaller = half_trace - radius;
    if (!(smaller > 0.0) || !std::isfinite(larger)) continue;  // degenerate 3D triangle
    stretches.angle[f] = 0.5 * std::atan2(2.0 * form(0, 1), form(0, 0) - form(1, 1));
    stretches.major[f] = std::sqrt(larger);
    stretches.minor[f] = std::sqrt(smaller);
  }
  return stretches;
}

FragmentRotationField::FragmentRotationField(const Mesh& mesh, Backend& backend,
                                             const SolverOptions& options)
    : mesh_(mesh) {
  const EdgeTable edges(mesh);
  const auto face_count = static_cast<int>(mesh.faces.rows());
  std::vector<Eigen::Triplet<double>> entries;
  for (int e = 0; e < edges.size(); ++e) {
    if (edges.face_count(e) != 2) continue;
    const auto uses = edges.uses(e);
    const int f = uses[0].face(), g = uses[1].face();
    first_face_.push_back(f);
    second_face_.push_back(g);
    edge_from_.push_back(mesh.faces(f, uses[0].corner()));
    edge_to_.push_back(mesh.faces(f, (uses[0].corner() + 1) % 3));
    entries.emplace_back(f, f, 1.0);
    entries.emplace_back(g, g, 1.0);
    entries.emplace_back(f, g, -1.0);
    entries.emplace_back(g, f, -1.0);
  }
  laplacian_.resize(face_count, face_count);
  laplacian_.setFromTriplets(entries.begin(), entries.end());
  laplacian_.makeCompressed();
  Eigen::VectorXi anchored(1);
  anchored[0] = 0;
  system_ = std::make_unique<DirichletSystem>(laplacian_, anchored, backend,
                                              MatrixKind::symmetric_positive_definite, options);
}

bool FragmentRotationField::factorize(SolveReport& report) {
  return system_->factorize(laplacian_, report);
}

bool FragmentRotationField::solve(const Eigen::MatrixX2d& uv, const TriangleStretches& stretches,
                                  double step, Eigen::VectorXd& theta, SolveReport& report) {
  // Normal equations of the least-squares problem: row f sums delta_e over its edges, with the
  // sign of f's side. Column 1 stays zero (the system solves two columns at once).
  Eigen::MatrixX2d load = Eigen::MatrixX2d::Zero(mesh_.faces.rows(), 2);
  for (std::size_t e = 0; e < first_face_.size(); ++e) {
    const Eigen::Vector2d edge = (uv.row(edge_to_[e]) - uv.row(edge_from_[e])).transpose();
    const Eigen::Vector2d as_first = stretches.power(first_face_[e], step) * edge;
    const Eigen::Vector2d as_second = stretches.power(second_face_[e], step) * edge;
    // theta_f - theta_g = arg(K_g e) - arg(K_f e): the angle from as_first to as_second.
    const double delta = std::atan2(as_first.x() * as_second.y() - as_first.y() * as_second.x(),
                                    as_first.dot(as_second));
    load(first_face_[e], 0) += delta;
    load(second_face_[e], 0) -= delta;
  }
  Eigen::MatrixX2d solution;
  if (!system_->solve(Eigen::MatrixX2d::Zero(1, 2), load, solution, report)) return false;
  theta = solution.col(0);
  return true;
}

Eigen::MatrixXd stretched_fragments(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                                    const TriangleStretches& stretches, double step,
                                    const Eigen::VectorXd& theta) {
  Eigen::MatrixXd fragments(3 * mesh.faces.rows(), 2);
  for (Eigen::Index f = 0; f < mesh.faces.rows(); ++f) {
    Eigen::Matrix2d shape = stretches.power(f, step);
    if (theta.size() > 0) shape = rotation(theta[f]) * shape;
    const Eigen::RowVector2d centroid =
        (uv.row(mesh.faces(f, 0)) + uv.row(mesh.faces(f, 1)) + uv.row(mesh.faces(f, 2))) / 3.0;
    for (int k = 0; k < 3; ++k)
      fragments.row(3 * f + k) = (shape * (uv.row(mesh.faces(f, k)) - centroid).transpose()).transpose();
  }
  return fragments;
}

}  // namespace harmonia::detail
