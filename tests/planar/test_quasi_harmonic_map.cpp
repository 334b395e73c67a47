// Quasi-harmonic maps (thesis chapter 5): exact flattening of developable surfaces from an
// ill-shaped start, self-correction on a hemisphere, regularized degenerate starts, reuse, errors.
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>

#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include "harmonia/boundary.h"
#include "harmonia/fixed_boundary_map.h"
#include "harmonia/io.h"
#include "harmonia/laplacian.h"
#include "harmonia/metrics.h"
#include "harmonia/procedural.h"
#include "harmonia/quasi_harmonic_map.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "harmonia/topology.h"
#include "support/test_support.h"
#include "support/topology_meshes.h"

namespace harmonia {
namespace {

constexpr double pi = std::numbers::pi;

// developable_strip's flat rectangle: vertex j*(nu+1)+i sits at (length*i/nu, width*j/nv).
struct Strip {
  int nu = 24, nv = 8;
  double length = 4.0, width = 1.5, radius = 1.2;
  Mesh mesh() const { return developable_strip(nu, nv, length, width, radius); }
  Eigen::MatrixX2d flat() const {
    Eigen::MatrixX2d uv((nu + 1) * (nv + 1), 2);
    for (int j = 0; j <= nv; ++j)
      for (int i = 0; i <= nu; ++i) uv.row(j * (nu + 1) + i) << length * i / nu, width * j / nv;
    return uv;
  }
  // A smooth non-affine warp that vanishes on the rectangle's boundary (so the boundary stays
  // at its isometric positions) and shears the interior strongly.
  Eigen::MatrixX2d warped() const {
    Eigen::MatrixX2d uv = flat();
    for (Eigen::Index v = 0; v < uv.rows(); ++v) {
      const double s = uv(v, 0) / length, t = uv(v, 1) / width;
      const double bump = std::sin(pi * s) * std::sin(pi * t);
      uv(v, 0) += 0.35 * length * bump * std::sin(pi * t) * (1.0 - s);
      uv(v, 1) += 0.25 * width * bump * std::cos(2.0 * pi * s);
    }
    return uv;
  }
};

double max_error_relative(const Eigen::MatrixX2d& uv, const Eigen::MatrixX2d& reference) {
  const double diameter = (reference.colwise().maxCoeff() - reference.colwise().minCoeff()).norm();
  return (uv - reference).rowwise().norm().maxCoeff() / diameter;
}

QuasiHarmonicOptions raw_options() {
  QuasiHarmonicOptions options;
  options.normalization = UvNormalization::none;
  options.solver.backend = BackendChoice::cpu;
  return options;
}

TEST(QuasiHarmonicMap, DevelopableStripConvergesToItsIsometricFlattening) {
  // The isometric flattening is a fixed point (C = identity there, and cotangent weights reproduce
  // a planar mesh); from a sheared start every round must bring the map closer to it. Measured: the
  // error shrinks by a factor of about 0.47 per round, 0.2 -> 1e-6 in about 17 rounds.
  const Strip strip;
  const Mesh mesh = strip.mesh();
  const Eigen::MatrixX2d flat = strip.flat(), start = strip.warped();
  QuasiHarmonicOptions options = raw_options();
  options.initial = InitialMap::given;
  options.initial_uv = start;
  options.stability_tolerance = 0.0;  // Run exactly max_rounds rounds.
  double previous = max_error_relative(start, flat);
  ASSERT_GT(previous, 0.1);  // Really ill-shaped.
  int rounds = 1;
  for (; rounds <= 30 && previous >= 1e-6; ++rounds) {
    options.max_rounds = rounds;  // Deterministic: run k reproduces the first k rounds of any run.
    const QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
    ASSERT_EQ(result.report.status, Status::ok) << result.report.message;
    ASSERT_EQ(result.report.rounds, rounds);
    const double error = max_error_relative(result.uv, flat);
    EXPECT_LT(error, previous) << "round " << rounds;
    previous = error;
  }
  std::cout << "strip: relative error " << previous << " after " << rounds - 1 << " rounds\n";
  EXPECT_LT(previous, 1e-6);
}

TEST(QuasiHarmonicMap, StopsWhenTheMapIsStable) {
  const Strip strip;
  QuasiHarmonicOptions options = raw_options();
  options.initial = InitialMap::given;
  options.initial_uv = strip.warped();
  options.max_rounds = 40;
  options.stability_tolerance = 1e-4;
  const QuasiHarmonicResult result = quasi_harmonic_map(strip.mesh(), options);
  ASSERT_EQ(result.report.status, Status::ok) << result.report.message;
  ASSERT_EQ(static_cast<int>(result.round_change.size()), result.report.rounds);
  EXPECT_LT(result.report.rounds, 40);
  EXPECT_LT(result.round_change.back(), 1e-4);
  for (std::size_t k = 0; k + 1 < result.round_change.size(); ++k)
    EXPECT_GE(result.round_change[k], 1e-4);
}

// The hemisphere's orthographic projection (x, y) with its interior twisted hard: a valid but
// ill-shaped start map whose boundary is the unit circle.
Eigen::MatrixX2d twisted_projection(const Mesh& mesh) {
  Eigen::MatrixX2d uv = mesh.vertices.leftCols<2>();
  for (Eigen::Index v = 0; v < uv.rows(); ++v) {
    const double r = uv.row(v).norm(), angle = 2.5 * (1.0 - r) * r;  // Zero at centre and rim.
    const Eigen::Vector2d p = uv.row(v);
    uv.row(v) << std::cos(angle) * p.x() - std::sin(angle) * p.y(),
        std::sin(angle) * p.x() + std::cos(angle) * p.y();
  }
  return uv;
}

TEST(QuasiHarmonicMap, HemisphereSelfCorrectsATwistedStart) {
  const Mesh mesh = hemisphere(16);
  QuasiHarmonicOptions options = raw_options();
  options.initial = InitialMap::given;
  options.initial_uv = twisted_projection(mesh);
  const DistortionMetrics start = evaluate_map(mesh, options.initial_uv, mesh.faces);
  const QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
  ASSERT_EQ(result.report.status, Status::ok) << result.report.message;
  const DistortionMetrics corrected = evaluate_map(mesh, result.uv, mesh.faces);

  FixedBoundaryOptions conformal_options;
  conformal_options.normalization = UvNormalization::none;
  const MapResult conformal = fixed_boundary_map(mesh, conformal_options);
  ASSERT_EQ(conformal.report.status, Status::ok);
  const DistortionMetrics conformal_metrics = evaluate_map(mesh, conformal.uv, mesh.faces);
  std::cout << "hemisphere: area distortion start " << start.area_distortion_mean << ", conformal "
            << conformal_metrics.area_distortion_mean << ", quasi-harmonic "
            << corrected.area_distortion_mean << " after " << result.report.rounds << " rounds; "
            << "conformal distortion start " << start.conformal_distortion_mean
            << ", quasi-harmonic " << corrected.conformal_distortion_mean << '\n';
  EXPECT_EQ(corrected.flipped_triangles, 0);
  EXPECT_EQ(result.report.flipped_triangles, 0);
  EXPECT_LT(corrected.area_distortion_mean, conformal_metrics.area_distortion_mean);
  EXPECT_LT(corrected.conformal_distortion_mean, start.conformal_distortion_mean);
}

TEST(QuasiHarmonicMap, StartMapsAllGiveValidMaps) {
  const Mesh mesh = demo_surface(12);
  for (const InitialMap initial : {InitialMap::conformal, InitialMap::plane_projection}) {
    for (const QuasiHarmonicWeights weights :
         {QuasiHarmonicWeights::tensor_cotangent, QuasiHarmonicWeights::tensor_mean_value}) {
      QuasiHarmonicOptions options;
      options.initial = initial;
      options.weights = weights;
      const QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
      EXPECT_EQ(result.report.status, Status::ok) << result.report.message;
      EXPECT_EQ(result.report.flipped_triangles, 0);
      EXPECT_GE(result.report.rounds, 1);
      EXPECT_LT(result.report.residual, 1e-10);
    }
  }
}

TEST(QuasiHarmonicMap, DegenerateStartIsRegularizedWithoutNaN) {
  // Every interior vertex of the start map at the centre: all interior triangles have zero UV
  // area, so no tensor exists there. They fall back to their 3D cotangent weights.
  const Mesh mesh = hemisphere(8);
  QuasiHarmonicOptions options = raw_options();
  options.initial = InitialMap::given;
  options.initial_uv = mesh.vertices.leftCols<2>();
  const int interior = 1 + 3 * 8 * 7;
  options.initial_uv.topRows(interior).setZero();
  const QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
  ASSERT_EQ(result.report.status, Status::ok) << result.report.message;
  EXPECT_TRUE(result.uv.allFinite());
  EXPECT_EQ(result.report.flipped_triangles, 0);
  EXPECT_EQ(result.report.degenerate_triangles, 0);
}

TEST(QuasiHarmonicMap, TwoRunsGiveIdenticalBits) {
  const Mesh mesh = demo_surface(10);
  const QuasiHarmonicResult first = quasi_harmonic_map(mesh), second = quasi_harmonic_map(mesh);
  ASSERT_EQ(first.report.status, Status::ok) << first.report.message;
  EXPECT_EQ(first.uv, second.uv);
  EXPECT_EQ(first.round_change, second.round_change);
}

TEST(QuasiHarmonicMap, ReusableMapperFollowsNewGeometry) {
  const Strip strip;
  const Mesh mesh = strip.mesh();
  QuasiHarmonicOptions options = raw_options();
  options.max_rounds = 3;
  QuasiHarmonicMapper mapper(mesh, options);
  const QuasiHarmonicResult first = mapper.solve();
  ASSERT_EQ(first.report.status, Status::ok) << first.report.message;
  // The same surface scaled: circle placement and tensors are scale-free, so the map is unchanged.
  mapper.update_geometry(2.0 * mesh.vertices);
  const QuasiHarmonicResult scaled = mapper.solve();
  ASSERT_EQ(scaled.report.status, Status::ok);
  EXPECT_LT((scaled.uv - first.uv).cwiseAbs().maxCoeff(), 1e-9);
}

using testing::octahedron;  // Closed, outward; vertices 4 and 5 are the poles.

TEST(QuasiHarmonicMap, ErrorsAreStatuses) {
  const QuasiHarmonicResult closed = quasi_harmonic_map(octahedron());
  EXPECT_EQ(closed.report.status, Status::not_a_disk);
  EXPECT_NE(closed.report.message.find("harmonia cut"), std::string::npos);

  QuasiHarmonicOptions options;
  options.initial = InitialMap::given;
  options.initial_uv = Eigen::MatrixX2d::Zero(3, 2);
  QuasiHarmonicResult result = quasi_harmonic_map(hemisphere(3), options);
  EXPECT_EQ(result.report.status, Status::invalid_input);
  EXPECT_NE(result.report.message.find("initial_uv has 3 rows"), std::string::npos)
      << result.report.message;

  options = {};
  options.max_rounds = 0;
  result = quasi_harmonic_map(hemisphere(3), options);
  EXPECT_EQ(result.report.status, Status::invalid_input);
  EXPECT_TRUE(result.uv.rows() == 0);
}

TEST(QuasiHarmonicMap, ProgressReportsRoundsAndCancels) {
  std::vector<std::string> stages;
  QuasiHarmonicOptions options;
  options.stability_tolerance = 0.0;
  options.max_rounds = 3;
  options.solver.progress = [&stages](const Progress& progress) {
    stages.emplace_back(progress.stage);
    return progress.stage != "round 2/3";
  };
  const QuasiHarmonicResult result = quasi_harmonic_map(hemisphere(6), options);
  EXPECT_EQ(result.report.status, Status::cancelled);
  EXPECT_EQ(result.uv.rows(), 0);
  EXPECT_NE(std::find(stages.begin(), stages.end(), "round 1/3"), stages.end());
  EXPECT_EQ(stages.back(), "round 2/3");
}

// The reference of ReusedFactorRoundsMatchExactRounds: the rounds of the quasi-harmonic map
// computed from the public operator functions with a fresh exact factorization (Eigen's LDLT) of
// every round, the boundary on the circle, a conformal start, and the library's stopping rule.
Eigen::MatrixX2d quasi_harmonic_reference(const Mesh& mesh, int max_rounds, double stability) {
  const std::vector<int> loop = boundary_loops(mesh).front();
  const BoundaryPlacement placement = place_boundary(mesh, loop, BoundaryOptions{});
  std::vector<int> free_index(static_cast<std::size_t>(mesh.vertex_count()), -1), free_vertices;
  std::vector<int> fixed_index(static_cast<std::size_t>(mesh.vertex_count()), -1);
  for (Eigen::Index k = 0; k < placement.vertices.size(); ++k)
    fixed_index[placement.vertices[k]] = static_cast<int>(k);
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    if (fixed_index[v] >= 0) continue;
    free_index[v] = static_cast<int>(free_vertices.size());
    free_vertices.push_back(v);
  }
  const auto n = static_cast<Eigen::Index>(free_vertices.size());
  const auto solve = [&](const Eigen::SparseMatrix<double>& operator_matrix) {
    std::vector<Eigen::Triplet<double>> interior;
    Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(n, 2);
    for (int column = 0; column < operator_matrix.outerSize(); ++column) {
      for (Eigen::SparseMatrix<double>::InnerIterator entry(operator_matrix, column); entry;
           ++entry) {
        const int row = free_index[entry.row()];
        if (row < 0) continue;
        if (free_index[column] >= 0)
          interior.emplace_back(row, free_index[column], entry.value());
        else
          rhs.row(row) -= entry.value() * placement.uv.row(fixed_index[column]);
      }
    }
    Eigen::SparseMatrix<double> matrix(n, n);
    matrix.setFromTriplets(interior.begin(), interior.end());
    const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(matrix);
    const Eigen::MatrixXd solution = factor.solve(rhs);
    Eigen::MatrixX2d uv(mesh.vertex_count(), 2);
    for (Eigen::Index k = 0; k < placement.vertices.size(); ++k)
      uv.row(placement.vertices[k]) = placement.uv.row(k);
    for (Eigen::Index i = 0; i < n; ++i) uv.row(free_vertices[i]) = solution.row(i);
    return uv;
  };
  Eigen::MatrixX2d uv = solve(laplacian(mesh, WeightScheme::cotangent));
  for (int round = 1; round <= max_rounds; ++round) {
    const Eigen::MatrixX2d next =
        solve(tensor_cotangent_laplacian(uv, mesh.faces, quasi_harmonic_tensors(mesh, uv)));
    const double diameter = (next.colwise().maxCoeff() - next.colwise().minCoeff()).norm();
    const double change = (next - uv).rowwise().norm().maxCoeff() / diameter;
    uv = next;
    if (change < stability) break;
  }
  return uv;
}

// Runs the default quasi-harmonic map (raw output) and compares it with the exact-rounds reference.
void expect_matches_exact_rounds(const Mesh& mesh, const std::string& name) {
  QuasiHarmonicOptions options;
  options.normalization = UvNormalization::none;
  options.solver.backend = BackendChoice::cpu;
  const QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
  ASSERT_EQ(result.report.status, Status::ok) << name << ": " << result.report.message;
  EXPECT_GT(result.report.iterations, 0) << name << ": no round reused a factorization";
  EXPECT_LT(result.report.residual, options.solver.tolerance) << name;
  const Eigen::MatrixX2d reference =
      quasi_harmonic_reference(mesh, options.max_rounds, options.stability_tolerance);
  ASSERT_EQ(reference.rows(), result.uv.rows());
  const double diameter = (reference.colwise().maxCoeff() - reference.colwise().minCoeff()).norm();
  const double difference = (result.uv - reference).rowwise().norm().maxCoeff() / diameter;
  std::cout << name << ": rounds " << result.report.rounds << ", stale-factor iterations "
            << result.report.iterations << ", max difference / diameter " << difference << "\n";
  EXPECT_LT(difference, 1e-6) << name;
}

TEST(QuasiHarmonicMap, ReusedFactorRoundsMatchExactRounds) {
  // Late rounds move the map little, so they are solved by conjugate gradients preconditioned with
  // an earlier round's Cholesky factor (report.iterations counts those iterations). The result must
  // be the map of exact solves in every round.
  expect_matches_exact_rounds(demo_surface(60), "demo surface");
}

TEST(QuasiHarmonicMap, ReusedFactorRoundsMatchExactRoundsOnTheFaceScan) {
  const std::filesystem::path path = testing::shared_data_dir() / "disk" / "face.obj";
  if (!std::filesystem::exists(path)) HARMONIA_SKIP_WITHOUT_CORPUS("no face scan at " << path);
  expect_matches_exact_rounds(read_mesh(path), "face.obj");
}

TEST(QuasiHarmonicMap, DefaultOptionsGiveAValidMapOnEveryCorpusDisk) {
  // The tensor-cotangent weights may be negative and fold a map (cow-cut: one triangle); then a
  // last round with the positive tensor mean-value weights on the circle cannot fold (Tutte).
  const auto meshes = testing::corpus_meshes("disk");
  if (meshes.empty()) HARMONIA_SKIP_WITHOUT_CORPUS("no disk corpus at " << (testing::shared_data_dir() / "disk"));
  bool fell_back = false;
  for (const auto& path : meshes) {
    const Mesh mesh = read_mesh(path);
    QuasiHarmonicOptions options;
    options.solver.backend = BackendChoice::cpu;
    const QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
    ASSERT_EQ(result.report.status, Status::ok) << path.filename() << ": " << result.report.message;
    const FlipCount flips = count_flips(result.uv, mesh.faces);
    EXPECT_EQ(flips.flipped + flips.zero_area, 0) << path.filename();
    fell_back = fell_back || !result.report.fallbacks.empty();
    if (path.filename() == "cow-cut.obj") {
      ASSERT_EQ(result.report.fallbacks.size(), 1u);
      EXPECT_NE(result.report.fallbacks[0].find("mean-value"), std::string::npos);
    }
  }
  std::cout << (fell_back ? "some" : "no") << " corpus disk needed the mean-value round\n";
}

}  // namespace
}  // namespace harmonia
