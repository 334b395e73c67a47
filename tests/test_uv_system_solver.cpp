// The pinned [u; v] conformal system: one Laplacian factor with a dense border system against the
// coupled blocks, and the bordered Cholesky factor's border block against the Schur complement.
#include <array>
#include <cmath>
#include <cstdio>
#include <string>

#include <Eigen/Cholesky>
#include <gtest/gtest.h>

#include "fallback/bordered_cholesky.h"
#include "harmonia/abf.h"
#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "host/detail/angle_constraints.h"
#include "host/detail/angle_reconstruction_least_squares.h"
#include "host/detail/lscm_energy.h"
#include "host/detail/uv_system_solver.h"
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
  solved.stats = solver.factorize(form);
  if (solved.stats.status == Status::ok) solved.stats = solver.solve(solved.uv);
  solved.name = solver.name();
  return solved;
}

bool one_factor(const Solved& solved) {
  return solved.name.find("one Laplacian factor") != std::string::npos;
}

// Both strategies on `form`: the same minimizer, residuals at rounding level.
void expect_strategies_agree(const std::string& what, const Eigen::SparseMatrix<double>& form,
                             const LayoutPins& pins) {
  const Solved shared = solve_with(form, pins, UvSystemStrategy::shared_laplacian);
  const Solved blocks = solve_with(form, pins, UvSystemStrategy::coupled_blocks);
  ASSERT_EQ(shared.stats.status, Status::ok) << what << ": " << shared.stats.message;
  ASSERT_EQ(blocks.stats.status, Status::ok) << what << ": " << blocks.stats.message;
  EXPECT_TRUE(one_factor(shared)) << what << ": " << shared.name;
  EXPECT_FALSE(one_factor(blocks)) << what << ": " << blocks.name;
  const double extent = (blocks.uv.colwise().maxCoeff() - blocks.uv.colwise().minCoeff()).maxCoeff();
  EXPECT_LT((shared.uv - blocks.uv).cwiseAbs().maxCoeff(), 1e-9 * extent) << what;
  EXPECT_LT(shared.stats.relative_residual, 1e-10) << what;
  EXPECT_LT(blocks.stats.relative_residual, 1e-10) << what;
  EXPECT_EQ(shared.uv.row(pins.first), Eigen::RowVector2d(0.0, 0.0)) << what;
  EXPECT_EQ(shared.uv.row(pins.second), Eigen::RowVector2d(pins.distance, 0.0)) << what;
}

TEST(BorderedCholesky, BorderBlockOfTheFactorIsTheSchurComplementsFactor) {
  const std::unique_ptr<detail::BorderedCholesky> factor = detail::make_bordered_cholesky();
  if (!factor) GTEST_SKIP() << "built without CHOLMOD";
  // The Dirichlet Laplacian of a jittered disk plus a small shift: SPD, sparse, connected.
  const Mesh mesh = planar_disk(6, 0.3);
  const Eigen::SparseMatrix<double> form =
      detail::lscm_quadratic_form(mesh, boundary_loops(mesh).front());
  const int n = mesh.vertex_count();
  Eigen::MatrixXd dense = Eigen::MatrixXd(form).topLeftCorner(n, n);
  dense += 0.01 * Eigen::MatrixXd::Identity(n, n);
  const Eigen::SparseMatrix<double> full = dense.sparseView();
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
  ASSERT_TRUE(factor->analyze(lower, ordering, border));
  ASSERT_TRUE(factor->factorize(lower));

  // Schur complement of the interior in the elimination order.
  Eigen::MatrixXd permuted(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) permuted(i, j) = dense(ordering[i], ordering[j]);
  const int inner = n - border;
  const Eigen::MatrixXd schur =
      permuted.bottomRightCorner(border, border) -
      permuted.bottomLeftCorner(border, inner) *
          permuted.topLeftCorner(inner, inner).llt().solve(permuted.topRightCorner(inner, border));
  const Eigen::MatrixXd block = factor->border_factor();
  EXPECT_LT((block * block.transpose() - schur).cwiseAbs().maxCoeff(), 1e-12 * schur.norm());
  EXPECT_EQ(Eigen::MatrixXd(block.triangularView<Eigen::StrictlyUpper>()).cwiseAbs().maxCoeff(),
            0.0);

  // forward then backward is the inverse of A.
  const Eigen::MatrixXd rhs = Eigen::MatrixXd::Random(n, 2);
  const Eigen::MatrixXd solution = factor->backward(factor->forward(rhs));
  EXPECT_LT((dense * solution - rhs).cwiseAbs().maxCoeff(), 1e-12 * rhs.cwiseAbs().maxCoeff());
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
    ASSERT_EQ(solver.factorize(form).status, Status::ok);
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
// 0) are consistent to 1e-15, and the reconstruction must give them back. The system is
// ill-conditioned: a direct solve leaves angle errors between 1e-10 and 2e-9 radians depending on
// the rounding of the factorization. A refinement step with the same factorization brings the
// residual down to the rounding level of the matrix-vector product (what fixed-precision
// refinement guarantees); the angle error it leaves must stay below 1e-9, which the turning
// angles of the convex boundary need (Abf.BoundaryControlOneConvergesOnTheAlligator).
TEST(UvSystemSolver, RefinementStepLowersTheResidualAndKeepsTheLayoutExact) {
  const Mesh mesh = read_mesh(testing::shared_data_dir() / "disk" / "alligator.obj");
  AbfOptions options;
  options.solver_options.backend = BackendChoice::cpu;
  options.boundary_t = 1.0;
  const AngleMapResult convex = abf(mesh, options);
  ASSERT_EQ(convex.report.status, Status::ok) << convex.report.message;
  ASSERT_LT(convex.report.constraint_residual, 1e-13);
  const std::vector<int> loop = boundary_loops(mesh).front();
  const Eigen::SparseMatrix<double> form = detail::sine_law_conformal_form(mesh, convex.angles);
  const LayoutPins pins{loop[0], loop[loop.size() / 3], 1.0};
  std::string message;
  const std::unique_ptr<detail::Backend> backend = detail::make_backend(BackendChoice::cpu, &message);
  UvSystemSolver solver(*backend, detail::IterativeSettings{}, ProgressCallback{});
  solver.analyze(form, pins, {});
  ASSERT_EQ(solver.factorize(form).status, Status::ok);
  Eigen::MatrixX2d plain, refined;
  const detail::SolveStats plain_stats = solver.solve(plain, 0);
  const detail::SolveStats refined_stats = solver.solve(refined, 1);
  ASSERT_EQ(plain_stats.status, Status::ok);
  ASSERT_EQ(refined_stats.status, Status::ok);
  const double plain_error = largest_angle_error(mesh, plain, convex.angles);
  const double refined_error = largest_angle_error(mesh, refined, convex.angles);
  std::printf("alligator, t = 1: relative residual %.3e, refined %.3e; largest angle error %.3e, "
              "refined %.3e\n",
              plain_stats.relative_residual, refined_stats.relative_residual, plain_error,
              refined_error);
  EXPECT_LE(refined_stats.relative_residual, plain_stats.relative_residual);
  EXPECT_LT(refined_stats.relative_residual, 1e-15);
  EXPECT_LT(refined_error, 1e-9);
}

}  // namespace
}  // namespace harmonia
