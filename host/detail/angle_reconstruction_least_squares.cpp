// Least-squares reconstruction of UVs from corner angles (thesis section 3.3, [SLMB05]).
//
// Every face asks the sine-law relation (angle_reconstruction_sine_law.h) of its vertices:
//   r_f = p_k - p_i - c_f (p_j - p_i) = 0,  c_f = (sin a_j / sin a_k) e^{i a_i},
// one complex equation per face, k the corner with the largest sine (so |c_f| <= 1). The three
// corner choices of a face all vanish on translations and on the triangle shape the angles
// describe: one equation per face suffices.
//
// The equation is that of a reference triangle, Z_i = 0, Z_j = 1, Z_k = c_f. Write the affine map
// from it to the UV triangle as z -> a z + b conj(z) + t; then p_j - p_i = a + b and
// p_k - p_i = a c + b conj(c), so r_f = b (conj(c) - c) and |r_f|^2 = 4 |b|^2 (Im c)^2. The
// conformal (LSCM) energy of that map is area_ref |grad u + rot90(grad v)|^2 = 4 area_ref |b|^2 =
// 2 Im c |b|^2: weighting |r_f|^2 by w_f = 1 / (2 Im c) makes the least-squares energy the
// conformal energy of the map from the reference triangles. That is still the least-squares
// solution of the sine-law relations (for consistent angles, the same exact layout), scale
// invariant per face, and it has the structure of LSCM (host/lscm.cpp):
//   * |grad u|^2 + |grad v|^2 over a triangle is the cotangent Dirichlet energy, with the
//     cotangents of the reference triangle's angles (the given angles when they sum to pi);
//   * the cross term is minus twice the signed UV area, which does not depend on the angles at
//     all, and whose sum over the mesh telescopes onto the boundary (the discrete natural
//     conformal identity): interior edges cancel exactly.
// So the normal matrix is [L N; N^T L], two cotangent Laplacians coupled only along the boundary,
// where the unweighted equations coupled u and v by a dense 2 x 2 block on every mesh edge; its
// Cholesky factor costs about two Laplacian factorizations instead of a 2 x 2-block one.
//
// Needle-thin reference triangles: angles near 0 or pi are rejected upstream, but a valid angle
// of 1e-9 would give a weight (and cotangents) of 1e9 and ruin the conditioning. The weight is
// capped at 1 / (2 kSmallestReferenceHeight): such a face keeps a fraction s = Im c / height of
// its conformal energy, so its Dirichlet part shrinks by s and its area part no longer cancels
// with its neighbours' (a coupling on its three edges, weighted 1 - s): the same bookkeeping as
// lscm.cpp's zero-area triangles, which are the case s = 0.
//
// Pinning two vertices removes the similarities (the kernel of the energy on a connected mesh),
// leaving Q_FF symmetric positive definite: Q_FF x_F = -Q_FP x_P goes to UvSystemSolver (one
// Laplacian factor for u and v on the CPU, the coupled blocks elsewhere).

#include "detail/angle_reconstruction_least_squares.h"

#include <algorithm>
#include <complex>
#include <string>

#include "detail/adjacency_pattern.h"

namespace harmonia::detail {

Eigen::SparseMatrix<double> sine_law_conformal_form(const Mesh& mesh,
                                                    const Eigen::MatrixX3d& angles) {
  const int vertex_count = mesh.vertex_count();
  AdjacencyPattern dirichlet(mesh.faces, vertex_count);
  AdjacencyPattern area(mesh.faces, vertex_count);
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d face_angles = angles.row(f).transpose();
    const SineLawRelation relation =
        sine_law_relation(face_angles, largest_sine_corner(face_angles));
    const std::complex<double> c = relation.factor;
    const double weight = sine_law_weight(relation);
    // cot(corner) * Im c for the reference triangle (0 at anchor, 1 at along, c at placed): the
    // dot product of the corner's two edges (their cross product is Im c at every corner).
    // Each edge (a, b) opposite a corner gets -cot/2 = -numerator * weight off the diagonal.
    const int anchor = mesh.faces(f, relation.anchor);
    const int along = mesh.faces(f, relation.along);
    const int placed = mesh.faces(f, relation.placed);
    const auto add_edge = [&dirichlet, weight](int a, int b, double numerator) {
      dirichlet.add(a, b, -numerator * weight);
      dirichlet.add(b, a, -numerator * weight);
    };
    add_edge(along, placed, c.real());
    add_edge(placed, anchor, 1.0 - c.real());
    add_edge(anchor, along, std::norm(c) - c.real());
    // Minus twice the signed UV area, sum over the directed edges x -> y of the face (in its
    // counter-clockwise order) of u_y v_x - u_x v_y: N(x, y) -= 1/2, N(y, x) += 1/2. Exactly 1
    // for uncapped faces, so that interior edges cancel to exact zeros.
    const double height = c.imag();
    const double share =
        height > kSmallestReferenceHeight ? 1.0 : height / kSmallestReferenceHeight;
    for (int k = 0; k < 3; ++k) {
      const int x = mesh.faces(f, k), y = mesh.faces(f, (k + 1) % 3);
      area.add(x, y, -0.5 * share);
      area.add(y, x, 0.5 * share);
    }
  }
  dirichlet.set_diagonal_from_rows();
  const Eigen::SparseMatrix<double> laplacian = dirichlet.take_matrix();
  const Eigen::SparseMatrix<double> coupling = area.take_matrix();

  // Q = [L N; N^T L] with N^T = -N, column by column, leaving out N's exact zeros.
  const Eigen::Index size = 2 * static_cast<Eigen::Index>(vertex_count);
  std::vector<int> outer{0}, inner;
  std::vector<double> values;
  inner.reserve(2 * static_cast<std::size_t>(laplacian.nonZeros()));
  values.reserve(2 * static_cast<std::size_t>(laplacian.nonZeros()));
  const auto append = [&](const Eigen::SparseMatrix<double>& matrix, int column, int row_offset,
                          double sign) {
    for (Eigen::SparseMatrix<double>::InnerIterator entry(matrix, column); entry; ++entry) {
      if (entry.value() == 0.0) continue;
      inner.push_back(row_offset + static_cast<int>(entry.row()));
      values.push_back(sign * entry.value());
    }
  };
  for (int column = 0; column < vertex_count; ++column) {  // u: L over -N.
    append(laplacian, column, 0, 1.0);
    append(coupling, column, vertex_count, -1.0);
    outer.push_back(static_cast<int>(inner.size()));
  }
  for (int column = 0; column < vertex_count; ++column) {  // v: N over L.
    append(coupling, column, 0, 1.0);
    append(laplacian, column, vertex_count, 1.0);
    outer.push_back(static_cast<int>(inner.size()));
  }
  Eigen::SparseMatrix<double> form(size, size);
  form.resizeNonZeros(static_cast<Eigen::Index>(inner.size()));
  std::copy(outer.begin(), outer.end(), form.outerIndexPtr());
  std::copy(inner.begin(), inner.end(), form.innerIndexPtr());
  std::copy(values.begin(), values.end(), form.valuePtr());
  return form;
}

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
  const Eigen::SparseMatrix<double> form = sine_law_conformal_form(mesh, angles);

  if (!clock.start("analysis")) return {};
  IterativeSettings settings;
  settings.relative_tolerance = options.tolerance;
  settings.max_iterations = options.max_iterations;
  UvSystemSolver solver(backend, settings, options.progress);
  solver.analyze(form, pins, vertex_ordering);

  if (!clock.start("factorization")) return {};
  const SolveStats factorization = solver.factorize(form);
  report.solver = solver.name();
  if (factorization.status != Status::ok) return fail(factorization.status, factorization.message);

  if (!clock.start("solve")) return {};
  Eigen::MatrixX2d uv;
  // The layout is to reproduce the angles: one step of iterative refinement takes the error of
  // its boundary angles from about 2e-9 to 4e-10 radians on alligator (a long, thin outline),
  // for one more pair of triangular solves.
  const SolveStats stats = solver.solve(uv, 1);
  report.iterations += stats.iterations;
  if (stats.status != Status::ok) return fail(stats.status, stats.message);
  report.residual = std::max(report.residual, stats.relative_residual);
  return uv;
}

}  // namespace harmonia::detail
