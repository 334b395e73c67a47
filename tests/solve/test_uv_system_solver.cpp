// The pinned [u; v] conformal system: one Laplacian factor with a dense border system against the
// coupled blocks, and the bordered Cholesky factor's border block against the Schur complement.
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include "abf/angle_constraints.h"
#include "abf/angle_reconstruction_least_squares.h"
#include "fallback/bordered_cholesky.h"
#include "fallback/direct_solvers.h"
#include "fallback/single_threaded_blas.h"
#include "fallback/subtree_parallel_cholesky.h"
#include "harmonia/abf.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "planar/lscm_energy.h"
#include "solve/backend_selection.h"
#include "solve/uv_system_solver.h"
#include "support/conditioning.h"
#include "support/test_support.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

using detail::LayoutPins;
using detail::UvSystemSolver;
using detail::UvSystemStrategy;

struct Solved {
  Eigen::MatrixX2d uv;
  detail::SolveStats stats;
  std::string name;
};

Solved solve_with(const Eigen::SparseMatrix<double>& form, const LayoutPins& pins,
                  UvSystemStrategy strategy) {
  std::string message;
  const std::unique_ptr<detail::Backend> backend = detail::make_backend(BackendChoice::cpu, &message);
  UvSystemSolver solver(*backend, detail::IterativeSettings{}, ProgressCallback{}, strategy);
  solver.analyze(form, pins, {});
  Solved solved;
  solved.stats = solver.factorize(Eigen::SparseMatrix<double>(form));
  if (solved.stats.status == Status::ok) solved.stats = solver.solve(solved.uv);
  solved.name = solver.name();
  return solved;
}

bool one_factor(const Solved& solved) {
  return solved.name.find("one Laplacian factor") != std::string::npos;
}

// Both strategies on `form`: the same minimizer, to the accuracy their residuals allow. Each
// layout x minimizes x^T Q x with the pins' four coordinates fixed, so its gradient on the free
// unknowns, r = (Q x)_free, is zero up to the solve's rounding; the two layouts' difference d on
// the free unknowns solves Q_ff d = r_shared - r_blocks, hence
//     |d|_2 <= (|r_shared| + |r_blocks|) / lambda_min(Q_ff),
// with each residual as computed here plus the rounding of computing it, and lambda_min estimated
// by inverse iteration (support/conditioning.h, with its margin).
void expect_strategies_agree(const std::string& what, const Eigen::SparseMatrix<double>& form,
                             const LayoutPins& pins) {
  const Solved shared = solve_with(form, pins, UvSystemStrategy::shared_laplacian);
  const Solved blocks = solve_with(form, pins, UvSystemStrategy::coupled_blocks);
  ASSERT_EQ(shared.stats.status, Status::ok) << what << ": " << shared.stats.message;
  ASSERT_EQ(blocks.stats.status, Status::ok) << what << ": " << blocks.stats.message;
  EXPECT_TRUE(one_factor(shared)) << what << ": " << shared.name;
  EXPECT_FALSE(one_factor(blocks)) << what << ": " << blocks.name;
  const auto vertices = static_cast<int>(shared.uv.rows());
  const std::vector<int> pinned{pins.first, pins.second, vertices + pins.first,
                                vertices + pins.second};
  const auto stacked = [](const Eigen::MatrixX2d& uv) {
    Eigen::VectorXd x(2 * uv.rows());
    x << uv.col(0), uv.col(1);
    return x;
  };
  const Eigen::VectorXd x_shared = stacked(shared.uv), x_blocks = stacked(blocks.uv);
  const auto residual_bound = [&](const Eigen::VectorXd& x) {
    return testing::without_entries(form * x, pinned).norm() +
           testing::product_rounding_bound(form, x);
  };
  const testing::SpdSpectrum spectrum =
      testing::spd_spectrum(testing::without_rows_and_columns(form, pinned));
  const double bound = testing::SpdSpectrum::kEstimateMargin *
                       (residual_bound(x_shared) + residual_bound(x_blocks)) / spectrum.smallest;
  EXPECT_LE((x_shared - x_blocks).norm(), bound)
      << what << ": condition number " << spectrum.condition();
  EXPECT_LT(shared.stats.relative_residual, 1e-10) << what;
  EXPECT_LT(blocks.stats.relative_residual, 1e-10) << what;
  EXPECT_EQ(shared.uv.row(pins.first), Eigen::RowVector2d(0.0, 0.0)) << what;
  EXPECT_EQ(shared.uv.row(pins.second), Eigen::RowVector2d(pins.distance, 0.0)) << what;
}

// The Dirichlet Laplacian of a jittered disk of `rings` rings plus a small shift (SPD, sparse,
// connected), its boundary loop as the border: the border block of the factor against the Schur
// complement of the interior, forward then backward against the matrix; returns the factor's name.
std::string expect_border_block_and_solves(int rings) {
  const std::unique_ptr<detail::BorderedCholesky> factor = detail::make_bordered_cholesky();
  const Mesh mesh = planar_disk(rings, 0.3);
  const Eigen::SparseMatrix<double> form =
      detail::lscm_quadratic_form(mesh, boundary_loops(mesh).front());
  const int n = mesh.vertex_count();
  Eigen::SparseMatrix<double> identity(n, n);
  identity.setIdentity();
  const Eigen::SparseMatrix<double> full =
      Eigen::SparseMatrix<double>(form.topLeftCorner(n, n)) + 0.01 * identity;
  const Eigen::SparseMatrix<double> lower = full.triangularView<Eigen::Lower>();
  // Border: the boundary loop, eliminated last.
  const std::vector<int> loop = boundary_loops(mesh).front();
  std::vector<char> in_loop(static_cast<std::size_t>(n), 0);
  for (const int v : loop) in_loop[static_cast<std::size_t>(v)] = 1;
  std::vector<int> ordering;
  for (int v = 0; v < n; ++v)
    if (!in_loop[static_cast<std::size_t>(v)]) ordering.push_back(v);
  ordering.insert(ordering.end(), loop.begin(), loop.end());
  const auto border = static_cast<int>(loop.size());
  EXPECT_TRUE(factor->analyze(lower, ordering, border));
  EXPECT_TRUE(factor->factorize(lower));

  // Schur complement of the interior in the elimination order (interior solves by Eigen's LLT).
  Eigen::PermutationMatrix<Eigen::Dynamic> to_order(n);
  for (int k = 0; k < n; ++k) to_order.indices()[ordering[static_cast<std::size_t>(k)]] = k;
  Eigen::SparseMatrix<double> permuted;
  permuted = lower.selfadjointView<Eigen::Lower>().twistedBy(to_order);
  const int inner = n - border;
  const Eigen::SparseMatrix<double> interior = permuted.topLeftCorner(inner, inner);
  const Eigen::MatrixXd coupling = Eigen::MatrixXd(permuted.topRightCorner(inner, border));
  const Eigen::SimplicialLLT<Eigen::SparseMatrix<double>> interior_factor(interior);
  const Eigen::MatrixXd schur = Eigen::MatrixXd(permuted.bottomRightCorner(border, border)) -
                                coupling.transpose() * interior_factor.solve(coupling);
  const Eigen::MatrixXd block = factor->border_factor();
  EXPECT_LT((block * block.transpose() - schur).cwiseAbs().maxCoeff(), 1e-12 * schur.norm());
  EXPECT_EQ(Eigen::MatrixXd(block.triangularView<Eigen::StrictlyUpper>()).cwiseAbs().maxCoeff(),
            0.0);

  // forward then backward is the inverse of A.
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(n, 2);
  const Eigen::MatrixXd solution = factor->backward(factor->forward(rhs));
  EXPECT_LT((full * solution - rhs).cwiseAbs().maxCoeff(), 1e-12 * rhs.cwiseAbs().maxCoeff());
  return factor->name();
}

TEST(BorderedCholesky, BorderBlockOfTheFactorIsTheSchurComplementsFactor) {
  if (!detail::make_bordered_cholesky()) GTEST_SKIP() << "built without CHOLMOD";
  // Below kCholmodSimplicialBelowRows the factor is simplicial, above it supernodal (one thread).
  const Mesh small = planar_disk(6, 0.3), large = planar_disk(38, 0.3);
  ASSERT_LT(small.vertex_count(), detail::kCholmodSimplicialBelowRows);
  ASSERT_GE(large.vertex_count(), detail::kCholmodSimplicialBelowRows);
  EXPECT_EQ(expect_border_block_and_solves(6), "cholmod-simplicial-llt");
  EXPECT_EQ(expect_border_block_and_solves(38), "cholmod-supernodal-llt");
}

// A system above the two-thread threshold (22K vertices): the border block and the solves of the
// split factorization against a sparse Schur complement and the matrix itself.
TEST(BorderedCholesky, LargeSystemsSplitOnTwoThreadsAndKeepTheirBorderBlock) {
  // A split needs the policy that lets harmonia hold OpenBLAS's thread count.
  const testing::ScopedBlasThreadPolicy hold(BlasThreadPolicy::hold_during_split_factorizations);
  const std::unique_ptr<detail::BorderedCholesky> factor = detail::make_bordered_cholesky();
  if (!factor) GTEST_SKIP() << "built without CHOLMOD";
  const Mesh mesh = planar_disk(85, 0.3);
  const int n = mesh.vertex_count();
  ASSERT_GE(n, detail::SubtreeParallelCholesky::kDefaultMinimumRows);
  Eigen::SparseMatrix<double> full = laplacian(mesh, WeightScheme::cotangent);
  for (int v = 0; v < n; ++v) full.coeffRef(v, v) += 0.01;
  const Eigen::SparseMatrix<double> lower = full.triangularView<Eigen::Lower>();
  // Nested dissection of the interior, the border last: an eighth of the boundary loop (a whole
  // loop of this disk would make the dense separator block too large for the split to pay).
  std::vector<int> loop = boundary_loops(mesh).front();
  loop.resize(loop.size() / 8);
  std::vector<int> interior_index(static_cast<std::size_t>(n), -1);
  std::vector<char> in_loop(static_cast<std::size_t>(n), 0);
  for (const int v : loop) in_loop[static_cast<std::size_t>(v)] = 1;
  std::vector<int> interior;
  for (int v = 0; v < n; ++v)
    if (!in_loop[static_cast<std::size_t>(v)]) {
      interior_index[static_cast<std::size_t>(v)] = static_cast<int>(interior.size());
      interior.push_back(v);
    }
  const auto inner = static_cast<int>(interior.size());
  const auto border = static_cast<int>(loop.size());
  std::vector<Eigen::Triplet<double>> inner_entries, coupling_entries;
  std::vector<int> loop_position(static_cast<std::size_t>(n), -1);
  for (int b = 0; b < border; ++b) loop_position[static_cast<std::size_t>(loop[b])] = b;
  for (int column = 0; column < n; ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(full, column); entry; ++entry) {
      const int row = static_cast<int>(entry.row());
      const int i = interior_index[static_cast<std::size_t>(row)];
      const int j = interior_index[static_cast<std::size_t>(column)];
      if (i >= 0 && j >= 0) inner_entries.emplace_back(i, j, entry.value());
      if (i >= 0 && j < 0)
        coupling_entries.emplace_back(i, loop_position[static_cast<std::size_t>(column)],
                                      entry.value());
    }
  Eigen::SparseMatrix<double> inner_matrix(inner, inner), coupling(inner, border);
  inner_matrix.setFromTriplets(inner_entries.begin(), inner_entries.end());
  coupling.setFromTriplets(coupling_entries.begin(), coupling_entries.end());
  const Eigen::SparseMatrix<double> inner_lower = inner_matrix.triangularView<Eigen::Lower>();
  std::vector<int> ordering;
  for (const int i : detail::nested_dissection_ordering(inner_lower))
    ordering.push_back(interior[static_cast<std::size_t>(i)]);
  ordering.insert(ordering.end(), loop.begin(), loop.end());
  ASSERT_TRUE(factor->analyze(lower, ordering, border));
  if (std::thread::hardware_concurrency() >= 2 && detail::SingleThreadedBlas::available()) {
    EXPECT_TRUE(factor->on_two_threads());
  }
  ASSERT_TRUE(factor->factorize(lower));

  // Schur complement of the interior: A_BB - A_BI A_II^-1 A_IB.
  const std::unique_ptr<detail::SparseSystemSolver> inner_solver = detail::make_cholesky_solver();
  inner_solver->analyze(inner_lower);
  ASSERT_EQ(inner_solver->factorize(inner_lower).status, Status::ok);
  Eigen::MatrixXd eliminated;
  ASSERT_EQ(inner_solver->solve(Eigen::MatrixXd(coupling), eliminated).status, Status::ok);
  Eigen::MatrixXd schur = -Eigen::MatrixXd(coupling.transpose()) * eliminated;
  for (int a = 0; a < border; ++a)
    for (int b = 0; b < border; ++b) schur(a, b) += full.coeff(loop[a], loop[b]);
  const Eigen::MatrixXd block = factor->border_factor();
  EXPECT_LT((block * block.transpose() - schur).cwiseAbs().maxCoeff(), 1e-12 * schur.norm());
  EXPECT_EQ(Eigen::MatrixXd(block.triangularView<Eigen::StrictlyUpper>()).cwiseAbs().maxCoeff(),
            0.0);
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(n, 2);
  const Eigen::MatrixXd solution = factor->backward(factor->forward(rhs));
  ASSERT_EQ(solution.rows(), n);
  EXPECT_LT((full * solution - rhs).cwiseAbs().maxCoeff(), 1e-10 * rhs.cwiseAbs().maxCoeff());
}

TEST(UvSystemSolver, StrategiesAgreeOnLscmWithAndWithoutZeroAreaTriangles) {
  if (!detail::make_bordered_cholesky()) GTEST_SKIP() << "built without CHOLMOD";
  Mesh collapsed = planar_disk(6, 0.2);
  collapsed.vertices.row(8) = collapsed.vertices.row(1);  // Two zero-area triangles inside.
  const std::pair<const char*, Mesh> meshes[] = {{"demo surface", demo_surface(12)},
                                                 {"hemisphere", hemisphere(8)},
                                                 {"disk with zero-area triangles", collapsed}};
  for (const auto& [name, mesh] : meshes) {
    const std::vector<int> loop = boundary_loops(mesh).front();
    const LayoutPins pins{loop[0], loop[loop.size() / 2], 1.7};
    expect_strategies_agree(name, detail::lscm_quadratic_form(mesh, loop), pins);
  }
}

TEST(UvSystemSolver, StrategiesAgreeOnTheAngleReconstructionOfCorpusMeshes) {
  if (!detail::make_bordered_cholesky()) GTEST_SKIP() << "built without CHOLMOD";
  for (const char* name : {"face", "alligator"}) {
    const Mesh mesh = read_mesh(testing::shared_data_dir() / "disk" / (std::string(name) + ".obj"));
    const std::vector<int> loop = boundary_loops(mesh).front();
    const LayoutPins pins{loop[0], loop[loop.size() / 3], 2.0};
    expect_strategies_agree(name, detail::sine_law_conformal_form(mesh, abf_target_angles(mesh)),
                            pins);
  }
}

TEST(UvSystemSolver, AutomaticChoiceFollowsTheBorderSize) {
  if (!detail::make_bordered_cholesky()) GTEST_SKIP() << "built without CHOLMOD";
  // face: a few hundred boundary vertices among 26K: one Laplacian factor.
  const Mesh face = read_mesh(testing::shared_data_dir() / "disk" / "face.obj");
  const std::vector<int> face_loop = boundary_loops(face).front();
  const Solved face_solved =
      solve_with(detail::lscm_quadratic_form(face, face_loop),
                 {face_loop[0], face_loop[face_loop.size() / 2], 1.0}, UvSystemStrategy::automatic);
  ASSERT_EQ(face_solved.stats.status, Status::ok);
  EXPECT_TRUE(one_factor(face_solved)) << face_solved.name;
  // A strip of triangles: every vertex on the boundary, so the dense border system would be the
  // whole problem: coupled blocks.
  const Mesh strip = testing::grid_disk(40, 1);
  const std::vector<int> strip_loop = boundary_loops(strip).front();
  const Solved strip_solved =
      solve_with(detail::lscm_quadratic_form(strip, strip_loop),
                 {strip_loop[0], strip_loop[strip_loop.size() / 2], 1.0},
                 UvSystemStrategy::automatic);
  ASSERT_EQ(strip_solved.stats.status, Status::ok);
  EXPECT_FALSE(one_factor(strip_solved)) << strip_solved.name;
}

TEST(UvSystemSolver, OneTriangleHasNoBorderAndIsReproduced) {
  if (!detail::make_bordered_cholesky()) GTEST_SKIP() << "built without CHOLMOD";
  Mesh triangle;
  triangle.vertices.resize(3, 3);
  triangle.vertices << 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.5, 1.5, 0.0;
  triangle.faces.resize(1, 3);
  triangle.faces << 0, 1, 2;
  const Solved solved = solve_with(detail::lscm_quadratic_form(triangle, {0, 1, 2}), {0, 1, 2.0},
                                   UvSystemStrategy::shared_laplacian);
  ASSERT_EQ(solved.stats.status, Status::ok) << solved.stats.message;
  EXPECT_TRUE(one_factor(solved)) << solved.name;
  EXPECT_LT((solved.uv.row(2) - Eigen::RowVector2d(0.5, 1.5)).norm(), 1e-12);
}

TEST(UvSystemSolver, RefactorizesNewValuesOnTheSamePattern) {
  if (!detail::make_bordered_cholesky()) GTEST_SKIP() << "built without CHOLMOD";
  const Mesh mesh = demo_surface(10);
  const std::vector<int> loop = boundary_loops(mesh).front();
  const LayoutPins pins{loop[0], loop[loop.size() / 2], 1.0};
  std::string message;
  const std::unique_ptr<detail::Backend> backend = detail::make_backend(BackendChoice::cpu, &message);
  UvSystemSolver solver(*backend, detail::IterativeSettings{}, ProgressCallback{},
                        UvSystemStrategy::shared_laplacian);
  Mesh bent = mesh;
  bent.vertices.col(2) *= 3.0;  // A different surface with the same faces.
  for (const Mesh* surface : std::array<const Mesh*, 2>{&mesh, &bent}) {
    const Eigen::SparseMatrix<double> form = detail::lscm_quadratic_form(*surface, loop);
    solver.analyze(form, pins, {});
    ASSERT_EQ(solver.factorize(Eigen::SparseMatrix<double>(form)).status, Status::ok);
    Eigen::MatrixX2d uv;
    ASSERT_EQ(solver.solve(uv).status, Status::ok);
    const Solved fresh = solve_with(form, pins, UvSystemStrategy::coupled_blocks);
    EXPECT_LT((uv - fresh.uv).cwiseAbs().maxCoeff(), 1e-10);
  }
}

// The largest difference between the corner angles of a layout and `angles` (#F x 3).
double largest_angle_error(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                           const Eigen::MatrixX3d& angles) {
  Mesh flat = mesh;
  flat.vertices.leftCols(2) = uv;
  flat.vertices.col(2).setZero();
  const Eigen::VectorXd laid_out = detail::corner_angles(flat);
  double largest = 0.0;
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k)
      largest = std::max(largest, std::abs(laid_out[3 * f + k] - angles(f, k)));
  return largest;
}

// Convex ABF angles of alligator (t = 1 folds its legs and tail inwards, with angles close to
// 0) are consistent to 1e-13, and the reconstruction must give them back. The pinned system is
// ill-conditioned (condition number about 3e8), so a solve's angle error depends on the rounding
// of its factorization. What one step of iterative refinement in fixed precision guarantees
// (Skeel 1980; Higham, Accuracy and Stability of Numerical Algorithms, theorem 12.3) is
// componentwise backward stability: |b - A x| <= gamma_{k+1} (|A| |x| + |b|) in every row, k the
// most entries of a row. The test checks that in every row, with gamma doubled for the rounding of
// computing the residual here. The layout's angle error is bounded by what the rounding can do:
// the same angles laid out with another pair of pins (a system of the same kind whose rounding
// errors are independent of the first's) gives angles that differ from the first layout's by the
// size of either's error; the refined layout's error must stay within 10 times that difference.
TEST(UvSystemSolver, RefinementStepIsBackwardStableAndKeepsTheLayoutAsExactAsItsConditioning) {
  const Mesh mesh = read_mesh(testing::shared_data_dir() / "disk" / "alligator.obj");
  AbfOptions options;
  options.solver_options.backend = BackendChoice::cpu;
  options.boundary_t = 1.0;
  const AngleMapResult convex = abf(mesh, options);
  ASSERT_EQ(convex.report.status, Status::ok) << convex.report.message;
  ASSERT_LT(convex.report.constraint_residual, 1e-13);
  const std::vector<int> loop = boundary_loops(mesh).front();
  const Eigen::SparseMatrix<double> form = detail::sine_law_conformal_form(mesh, convex.angles);
  std::string message;
  const std::unique_ptr<detail::Backend> backend = detail::make_backend(BackendChoice::cpu, &message);
  const auto layout = [&](const LayoutPins& pins, int refinement_steps) {
    UvSystemSolver solver(*backend, detail::IterativeSettings{}, ProgressCallback{});
    solver.analyze(form, pins, {});
    EXPECT_EQ(solver.factorize(Eigen::SparseMatrix<double>(form)).status, Status::ok);
    Eigen::MatrixX2d uv;
    EXPECT_EQ(solver.solve(uv, refinement_steps).status, Status::ok);
    return uv;
  };
  const LayoutPins pins{loop[0], loop[loop.size() / 3], 1.0};
  const Eigen::MatrixX2d refined = layout(pins, 1);

  // Componentwise backward stability of the refined layout, row by row of the free unknowns.
  const int n = mesh.vertex_count();
  Eigen::VectorXd x(2 * n);
  x << refined.col(0), refined.col(1);
  std::vector<char> pinned(static_cast<std::size_t>(2 * n), 0);
  for (const int unknown : {pins.first, pins.second, n + pins.first, n + pins.second})
    pinned[static_cast<std::size_t>(unknown)] = 1;
  const Eigen::VectorXd residual = form * x;  // -(b - A x) on the free rows.
  Eigen::VectorXd magnitude = Eigen::VectorXd::Zero(2 * n);  // (|A| |x| + |b|), bounded above.
  Eigen::VectorXi row_entries = Eigen::VectorXi::Zero(2 * n);
  for (Eigen::Index column = 0; column < form.outerSize(); ++column)
    for (Eigen::SparseMatrix<double>::InnerIterator entry(form, column); entry; ++entry) {
      magnitude(entry.row()) += std::abs(entry.value() * x(entry.col()));
      ++row_entries(entry.row());
    }
  const double eps = std::numeric_limits<double>::epsilon();
  const double k = row_entries.maxCoeff() + 1.0;
  const double gamma = k * eps / (1.0 - k * eps);
  double worst_share = 0.0;
  for (int row = 0; row < 2 * n; ++row) {
    if (pinned[static_cast<std::size_t>(row)]) continue;
    const double allowed = 2.0 * gamma * magnitude(row);
    EXPECT_LE(std::abs(residual(row)), allowed) << "row " << row;
    if (allowed > 0.0) worst_share = std::max(worst_share, std::abs(residual(row)) / allowed);
  }

  // The angle error, against the rounding's own size.
  const Eigen::MatrixX2d other = layout({loop[loop.size() / 2], loop[(5 * loop.size()) / 6], 1.0}, 1);
  const double error = largest_angle_error(mesh, refined, convex.angles);
  const double rounding = largest_angle_error(mesh, refined, [&] {
    Mesh flat = mesh;
    flat.vertices.leftCols(2) = other;
    flat.vertices.col(2).setZero();
    const Eigen::VectorXd corners = detail::corner_angles(flat);
    Eigen::MatrixX3d angles(mesh.face_count(), 3);
    for (int f = 0; f < mesh.face_count(); ++f)
      for (int c = 0; c < 3; ++c) angles(f, c) = corners[3 * f + c];
    return angles;
  }());
  std::printf("alligator, t = 1: worst row of the residual at %.3f of its bound; largest angle "
              "error %.3e, difference to another pinning %.3e\n",
              worst_share, error, rounding);
  EXPECT_LE(error, 10.0 * rounding);
}

}  // namespace
}  // namespace harmonia
