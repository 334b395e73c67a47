// Least-squares reconstruction of UVs from corner angles (thesis section 3.3, [SLMB05]).
//
// Every face asks the sine-law relation (angle_reconstruction_sine_law.h) of its vertices:
//   r_f = p_k - p_i - c_f (p_j - p_i) = 0,  c_f = (sin a_j / sin a_k) e^{i a_i},
// one complex equation per face. The three corner choices of a face all vanish on translations
// and on the triangle shape the angles describe, so for angles summing to pi they are multiples of
// one another: using all three would only reweight the face. One equation per face suffices; we
// take the corner with the largest sine as k, so |c_f| <= 1 and no equation amplifies angle
// error. The residual is measured in uv lengths, so a face weighs with its size (as the
// area-weighted conformal energy does) without an explicit weight.
//
// E(z) = sum_f |r_f|^2 = z^H H z with the Hermitian H = sum_f conj(w_f) w_f^T (w_f: the three
// coefficients of r_f). Written in the real unknowns (u_0, v_0, u_1, v_1, ...) with H = S + iK
// (S symmetric, K antisymmetric), E = x^T Q x with the 2 x 2 blocks Q_ab = [S_ab -K_ab; K_ab S_ab].
// H has the vertex adjacency pattern, so it is accumulated in place (AdjacencyPattern, O(F)) and
// Q inherits the pattern of the vertex operator with every entry a 2 x 2 block: the vertex
// ordering of the operator expands to a good ordering of Q. E is invariant under similarities
// (z -> a z + b); pinning two vertices removes exactly those, leaving Q_FF symmetric positive
// definite: its normal equations Q_FF x_F = -Q_FP x_P go to the backend's SPD solver.

#include "detail/angle_reconstruction_least_squares.h"

#include <algorithm>
#include <complex>
#include <string>

#include "detail/adjacency_pattern.h"
#include "detail/angle_reconstruction_sine_law.h"

namespace harmonia::detail {
namespace {

// The real and imaginary parts of H = sum_f conj(w_f) w_f^T, as two #V x #V matrices with the
// vertex adjacency pattern (the same pattern for both).
struct HermitianForm {
  Eigen::SparseMatrix<double> real;
  Eigen::SparseMatrix<double> imaginary;
};

HermitianForm assemble_sine_law_form(const Mesh& mesh, const Eigen::MatrixX3d& angles) {
  AdjacencyPattern real(mesh.faces, mesh.vertex_count());
  AdjacencyPattern imaginary(mesh.faces, mesh.vertex_count());
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d face_angles = angles.row(f).transpose();
    const SineLawRelation relation =
        sine_law_relation(face_angles, largest_sine_corner(face_angles));
    // r_f = 1 p_k + (c - 1) p_i - c p_j.
    std::complex<double> coefficient[3];
    coefficient[relation.placed] = 1.0;
    coefficient[relation.anchor] = relation.factor - 1.0;
    coefficient[relation.along] = -relation.factor;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        const std::complex<double> entry = std::conj(coefficient[a]) * coefficient[b];
        real.add(mesh.faces(f, a), mesh.faces(f, b), entry.real());
        imaginary.add(mesh.faces(f, a), mesh.faces(f, b), entry.imag());
      }
    }
  }
  return {real.take_matrix(), imaginary.take_matrix()};
}

// Q_FF in the interleaved free unknowns (2 n, 2 n + 1 for the n-th free vertex) and the
// right-hand side -Q_FP x_P (only the second pin is away from the origin, along u).
struct FreeSystem {
  Eigen::SparseMatrix<double> matrix;
  Eigen::VectorXd rhs;
};

FreeSystem split_free_system(const HermitianForm& form, const std::vector<int>& free_index,
                             const LayoutPins& pins) {
  const auto vertex_count = static_cast<int>(free_index.size());
  const Eigen::Index size = 2 * (static_cast<Eigen::Index>(vertex_count) - 2);
  const Eigen::SparseMatrix<double>& s = form.real;
  const Eigen::SparseMatrix<double>& k = form.imaginary;
  std::vector<int> outer{0}, inner;
  std::vector<double> values;
  inner.reserve(4 * static_cast<std::size_t>(s.nonZeros()));
  values.reserve(4 * static_cast<std::size_t>(s.nonZeros()));
  // Column u_b holds (S_ab, K_ab) in rows (u_a, v_a); column v_b holds (-K_ab, S_ab). The free
  // index grows with the vertex, so the rows of every column come out sorted.
  for (int b = 0; b < vertex_count; ++b) {
    if (free_index[b] < 0) continue;
    for (const bool v_column : {false, true}) {
      const double* s_values = s.valuePtr() + s.outerIndexPtr()[b];
      const double* k_values = k.valuePtr() + k.outerIndexPtr()[b];
      const int* rows = s.innerIndexPtr() + s.outerIndexPtr()[b];
      const int count = s.outerIndexPtr()[b + 1] - s.outerIndexPtr()[b];
      for (int n = 0; n < count; ++n) {
        const int row = free_index[rows[n]];
        if (row < 0) continue;
        inner.push_back(2 * row);
        values.push_back(v_column ? -k_values[n] : s_values[n]);
        inner.push_back(2 * row + 1);
        values.push_back(v_column ? s_values[n] : k_values[n]);
      }
      outer.push_back(static_cast<int>(inner.size()));
    }
  }
  FreeSystem system;
  system.matrix.resize(size, size);
  system.matrix.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), system.matrix.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), system.matrix.innerIndexPtr());
  std::copy(values.begin(), values.end(), system.matrix.valuePtr());

  system.rhs = Eigen::VectorXd::Zero(size);
  for (Eigen::SparseMatrix<double>::InnerIterator entry(s, pins.second); entry; ++entry) {
    const int row = free_index[entry.row()];
    if (row < 0) continue;
    system.rhs[2 * row] = -pins.distance * entry.value();
    system.rhs[2 * row + 1] = -pins.distance * k.coeff(entry.row(), pins.second);
  }
  return system;
}

}  // namespace

Eigen::MatrixX2d least_squares_layout(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                      const LayoutPins& pins, Backend& backend,
                                      const SolverOptions& options,
                                      const std::vector<int>& vertex_ordering,
                                      SolveReport& report, PhaseClock& clock) {
  const auto fail = [&report](Status status, const std::string& message) {
    report.status = status;
    report.message = "angles_to_uv: " + message;
    return Eigen::MatrixX2d();
  };
  if (!clock.start("assembly")) return {};
  const int vertex_count = mesh.vertex_count();
  std::vector<int> free_index(static_cast<std::size_t>(vertex_count), -1);
  int free_count = 0;
  for (int v = 0; v < vertex_count; ++v)
    if (v != pins.first && v != pins.second) free_index[v] = free_count++;
  const FreeSystem system = split_free_system(assemble_sine_law_form(mesh, angles), free_index, pins);

  if (!clock.start("analysis")) return {};
  IterativeSettings settings;
  settings.relative_tolerance = options.tolerance;
  settings.max_iterations = options.max_iterations;
  const std::unique_ptr<SparseSystemSolver> solver = make_system_solver(
      backend, MatrixKind::symmetric_positive_definite, settings, options.progress);
  report.solver = solver->name();
  if (vertex_ordering.size() == static_cast<std::size_t>(vertex_count)) {
    std::vector<int> ordering;  // Each free vertex's two unknowns, in the vertex ordering.
    ordering.reserve(2 * static_cast<std::size_t>(free_count));
    for (const int v : vertex_ordering) {
      if (free_index[v] < 0) continue;
      ordering.push_back(2 * free_index[v]);
      ordering.push_back(2 * free_index[v] + 1);
    }
    solver->analyze_with_ordering(system.matrix, ordering);
  } else {
    solver->analyze(system.matrix);
  }

  if (!clock.start("factorization")) return {};
  const SolveStats factorization = solver->factorize(system.matrix);
  if (factorization.status != Status::ok) return fail(factorization.status, factorization.message);

  if (!clock.start("solve")) return {};
  Eigen::MatrixXd solution;
  const SolveStats stats = solver->solve(system.rhs, solution);
  report.iterations += stats.iterations;
  if (stats.status != Status::ok) return fail(stats.status, stats.message);
  const double rhs_norm = system.rhs.norm();
  const double residual = (system.matrix * solution.col(0) - system.rhs).norm();
  report.residual = std::max(report.residual, rhs_norm > 0.0 ? residual / rhs_norm : residual);

  Eigen::MatrixX2d uv(vertex_count, 2);
  for (int v = 0; v < vertex_count; ++v) {
    if (free_index[v] < 0) continue;
    uv(v, 0) = solution(2 * free_index[v], 0);
    uv(v, 1) = solution(2 * free_index[v] + 1, 0);
  }
  uv.row(pins.first) << 0.0, 0.0;
  uv.row(pins.second) << pins.distance, 0.0;
  return uv;
}

}  // namespace harmonia::detail
