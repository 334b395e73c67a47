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
// invariant per face, and it has the structure of LSCM (host/planar/lscm.cpp):
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

#include "abf/angle_reconstruction_least_squares.h"

#include <algorithm>
#include <complex>
#include <numbers>
#include <future>
#include <string>
#include <thread>
#include <utility>

#include "mesh/adjacency_pattern.h"
#include "mesh/helper_tasks.h"

namespace harmonia::detail {

namespace {

// Index of the ordered pair of a face's corners (i, j), i != j, among its six.
constexpr int kPairSlot[3][3] = {{-1, 0, 1}, {2, -1, 3}, {4, 5, -1}};

// A face whose angles all lie in [kSurelyFullShareAngle, pi - kSurelyFullShareAngle] has a
// reference height Im factor = sin a_along sin a_anchor / sin a_placed >= sin(0.01)^2, about
// 1e-4, far above kSmallestReferenceHeight: its full area share is known without a sine.
constexpr double kSurelyFullShareAngle = 0.01;

// The fraction of a face's conformal energy kept by the capped weight (1 for all but needle-thin
// reference triangles; see the top of this file).
double area_share(double height) {
  return height > kSmallestReferenceHeight ? 1.0 : height / kSmallestReferenceHeight;
}

// Minus twice the signed UV area of a face, sum over its directed edges x -> y (counter-clockwise)
// of u_y v_x - u_x v_y: N(x, y) -= 1/2, N(y, x) += 1/2, scaled by the face's share. Exactly 1/2 for
// uncapped faces, so that interior edges cancel to exact zeros.
void add_area_coupling(std::vector<double>& area, const int* places, double share) {
  for (int k = 0; k < 3; ++k) {
    const int x = k, y = (k + 1) % 3;
    area[static_cast<std::size_t>(places[kPairSlot[x][y]])] += -0.5 * share;
    area[static_cast<std::size_t>(places[kPairSlot[y][x]])] += 0.5 * share;
  }
}


}  // namespace

SineLawFormAssembler::SineLawFormAssembler(const Mesh& mesh) : mesh_(mesh) {
  const int vertex_count = mesh.vertex_count();
  AdjacencyPattern adjacency(mesh.faces, vertex_count);
  const auto place = [&adjacency](int row, int column) {
    return static_cast<int>(std::lower_bound(adjacency.column_begin(column),
                                             adjacency.column_end(column), row) -
                            adjacency.column_begin(0));
  };
  diagonal_.resize(static_cast<std::size_t>(vertex_count));
  for (int v = 0; v < vertex_count; ++v) diagonal_[static_cast<std::size_t>(v)] = place(v, v);
  face_places_.resize(6 * static_cast<std::size_t>(mesh.face_count()));
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (i != j)
          face_places_[6 * static_cast<std::size_t>(f) + static_cast<std::size_t>(kPairSlot[i][j])] =
              place(mesh.faces(f, i), mesh.faces(f, j));
  pattern_ = adjacency.take_matrix();
}

namespace {
// Below this many faces the relations take a few milliseconds: one thread computes them.
constexpr int kSmallestSplitFaceCount = 50000;
}  // namespace

Eigen::SparseMatrix<double> SineLawFormAssembler::assemble(const Eigen::MatrixX3d& angles) const {
  const int vertex_count = mesh_.vertex_count();
  const auto entry_count = static_cast<std::size_t>(pattern_.nonZeros());
  std::vector<double> dirichlet(entry_count, 0.0), area(entry_count, 0.0);
  // The faces' relations (their sines and cosines, most of the work) on two threads for a large
  // mesh, then scattered in face order on this one (the same sums as before, bit for bit).
  const int face_count = mesh_.face_count();
  std::vector<SineLawRelation> relations(static_cast<std::size_t>(face_count));
  const auto relate = [&](int begin, int end) {
    for (int f = begin; f < end; ++f) {
      const Eigen::Vector3d face_angles = angles.row(f).transpose();
      relations[static_cast<std::size_t>(f)] =
          sine_law_relation(face_angles, largest_sine_corner(face_angles));
    }
  };
  if (face_count >= kSmallestSplitFaceCount && std::thread::hardware_concurrency() >= 2) {
    auto second_half = start_beside([&] { relate(face_count / 2, face_count); });
    relate(0, face_count / 2);
    second_half.get();
  } else {
    relate(0, face_count);
  }
  for (int f = 0; f < face_count; ++f) {
    const int* places = face_places_.data() + 6 * static_cast<std::size_t>(f);
    const SineLawRelation& relation = relations[static_cast<std::size_t>(f)];
    const std::complex<double> c = relation.factor;
    const double weight = sine_law_weight(relation);
    // cot(corner) * Im c for the reference triangle (0 at anchor, 1 at along, c at placed): the
    // dot product of the corner's two edges (their cross product is Im c at every corner).
    // Each edge (a, b) opposite a corner gets -cot/2 = -numerator * weight off the diagonal.
    const auto add_edge = [&](int a, int b, double numerator) {
      dirichlet[static_cast<std::size_t>(places[kPairSlot[a][b]])] += -numerator * weight;
      dirichlet[static_cast<std::size_t>(places[kPairSlot[b][a]])] += -numerator * weight;
    };
    add_edge(relation.along, relation.placed, c.real());
    add_edge(relation.placed, relation.anchor, 1.0 - c.real());
    add_edge(relation.anchor, relation.along, std::norm(c) - c.real());
    add_area_coupling(area, places, area_share(c.imag()));
  }
  // The Laplacian's diagonal: minus the sum of the off-diagonal entries of its row.
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  std::vector<double> off_diagonal_sum(static_cast<std::size_t>(vertex_count), 0.0);
  for (int c = 0; c < vertex_count; ++c)
    for (int k = outer[c]; k < outer[c + 1]; ++k)
      if (inner[k] != c)
        off_diagonal_sum[static_cast<std::size_t>(inner[k])] += dirichlet[static_cast<std::size_t>(k)];
  for (int c = 0; c < vertex_count; ++c)
    dirichlet[static_cast<std::size_t>(diagonal_[static_cast<std::size_t>(c)])] =
        -off_diagonal_sum[static_cast<std::size_t>(c)];

  return form_of(&dirichlet, area);
}

Eigen::SparseMatrix<double> SineLawFormAssembler::pattern(const Eigen::MatrixX3d& angles) const {
  std::vector<double> area(static_cast<std::size_t>(pattern_.nonZeros()), 0.0);
  for (int f = 0; f < mesh_.face_count(); ++f) {
    const Eigen::Vector3d face_angles = angles.row(f).transpose();
    const bool surely_full = face_angles.minCoeff() >= kSurelyFullShareAngle &&
                             face_angles.maxCoeff() <= std::numbers::pi - kSurelyFullShareAngle;
    // The same share, bit for bit, as assemble() gives the face: the same sums, the same zeros.
    const double share =
        surely_full ? 1.0
                    : area_share(sine_law_relation(face_angles, largest_sine_corner(face_angles))
                                     .factor.imag());
    add_area_coupling(area, face_places_.data() + 6 * static_cast<std::size_t>(f), share);
  }
  return form_of(nullptr, area);
}

Eigen::SparseMatrix<double> SineLawFormAssembler::form_of(const std::vector<double>* dirichlet,
                                                          const std::vector<double>& area) const {
  const int vertex_count = mesh_.vertex_count();
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  // Q = [L N; N^T L] with N^T = -N, column by column: every entry of L (its pattern is the vertex
  // adjacency, whatever the angles) and the nonzeros of N (which cancel to exact zeros on
  // interior edges). The entries are counted, then written straight into the matrix.
  const Eigen::Index size = 2 * static_cast<Eigen::Index>(vertex_count);
  const auto nonzeros_in = [&](const std::vector<double>& values, int column) {
    int count = 0;
    for (int k = outer[column]; k < outer[column + 1]; ++k)
      count += values[static_cast<std::size_t>(k)] != 0.0 ? 1 : 0;
    return count;
  };
  Eigen::SparseMatrix<double> form(size, size);
  int* form_outer = form.outerIndexPtr();
  form_outer[0] = 0;
  for (int column = 0; column < vertex_count; ++column) {
    const int count = (outer[column + 1] - outer[column]) + nonzeros_in(area, column);
    form_outer[column + 1] = count;                 // u's column: L over -N.
    form_outer[vertex_count + column + 1] = count;  // v's column: N over L.
  }
  for (Eigen::Index column = 0; column < size; ++column) form_outer[column + 1] += form_outer[column];
  form.resizeNonZeros(form_outer[size]);
  int* form_inner = form.innerIndexPtr();
  double* form_values = form.valuePtr();
  int next = 0;
  const auto append_laplacian = [&](int column, int row_offset) {
    for (int k = outer[column]; k < outer[column + 1]; ++k) {
      form_inner[next] = row_offset + inner[k];
      form_values[next++] = dirichlet != nullptr ? (*dirichlet)[static_cast<std::size_t>(k)] : 0.0;
    }
  };
  const auto append_coupling = [&](int column, int row_offset, double sign) {
    for (int k = outer[column]; k < outer[column + 1]; ++k) {
      const double value = area[static_cast<std::size_t>(k)];
      if (value == 0.0) continue;
      form_inner[next] = row_offset + inner[k];
      form_values[next++] = sign * value;
    }
  };
  for (int column = 0; column < vertex_count; ++column) {
    append_laplacian(column, 0);
    append_coupling(column, vertex_count, -1.0);
  }
  for (int column = 0; column < vertex_count; ++column) {
    append_coupling(column, 0, 1.0);
    append_laplacian(column, vertex_count);
  }
  return form;
}

Eigen::SparseMatrix<double> sine_law_conformal_form(const Mesh& mesh,
                                                    const Eigen::MatrixX3d& angles) {
  return SineLawFormAssembler(mesh).assemble(angles);
}

LeastSquaresLayout::LeastSquaresLayout(const Mesh& mesh, const LayoutPins& pins,
                                       Backend& backend, const SolverOptions& options)
    : assembler_(mesh), pins_(pins), solver_(backend, iterative_settings(options), options.progress) {
  if (options.backend == BackendChoice::automatic) solver_.allow_cpu_retry();
}

void LeastSquaresLayout::set_vertex_ordering(std::vector<int> vertex_ordering) {
  vertex_ordering_ = std::move(vertex_ordering);
}

void LeastSquaresLayout::analyze(const Eigen::MatrixX3d& predicted) {
  solver_.analyze(assembler_.pattern(predicted), pins_, vertex_ordering_);
}

Eigen::MatrixX2d LeastSquaresLayout::layout(const Eigen::MatrixX3d& angles, SolveReport& report,
                                            PhaseClock& clock) {
  const auto fail = [&report](Status status, const std::string& message) {
    report.status = status;
    report.message = "angles_to_uv: " + message;
    return Eigen::MatrixX2d();
  };
  if (!clock.start("assembly")) return {};
  Eigen::SparseMatrix<double> form = assembler_.assemble(angles);

  if (!clock.start("analysis")) return {};
  solver_.analyze(form, pins_, vertex_ordering_);  // Nothing to do for an analyzed pattern.

  if (!clock.start("factorization")) return {};
  const SolveStats factorization = solver_.factorize(std::move(form));
  report.solver = solver_.name();
  if (std::string notice = solver_.take_cpu_retry_notice(); !notice.empty()) report.fallbacks.push_back(notice);
  if (factorization.status != Status::ok) return fail(factorization.status, factorization.message);

  if (!clock.start("solve")) return {};
  Eigen::MatrixX2d uv;
  // The layout is to reproduce the angles: one step of iterative refinement brings the residual
  // to the rounding level of the product (see UvSystemSolver::solve), for one more pair of
  // triangular solves.
  const SolveStats stats = solver_.solve(uv, 1);
  report.iterations += stats.iterations;
  if (std::string notice = solver_.take_cpu_retry_notice(); !notice.empty()) {
    report.fallbacks.push_back(notice);
    report.solver = solver_.name();
  }
  if (stats.status != Status::ok) return fail(stats.status, stats.message);
  report.residual = std::max(report.residual, stats.relative_residual);
  return uv;
}

Eigen::MatrixX2d least_squares_layout(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                      const LayoutPins& pins, Backend& backend,
                                      const SolverOptions& options,
                                      const std::vector<int>& vertex_ordering,
                                      SolveReport& report, PhaseClock& clock) {
  LeastSquaresLayout system(mesh, pins, backend, options);
  system.set_vertex_ordering(vertex_ordering);
  return system.layout(angles, report, clock);
}

}  // namespace harmonia::detail
