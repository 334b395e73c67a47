// Nonlinear ABF (thesis chapter 2): validity on the obtuse fan, planar meshes reproduced, the
// boundary control coefficient t of (2.6), every step solver reaching the same angles, the
// underdetermined variant, the corpus, bad input, progress, and the Vulkan backend against the CPU.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "harmonia/abf.h"
#include "harmonia/angles_to_uv.h"
#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "support/angle_test_meshes.h"
#include "support/test_support.h"
#include "support/vulkan_test_support.h"

namespace harmonia::testing {
namespace {

constexpr double kPi = std::numbers::pi;

// The mesh's own corner angles (#F x 3), angles(f, k) at faces(f, k).
Eigen::MatrixX3d mesh_angles(const Eigen::MatrixXd& points, const Eigen::MatrixX3i& faces) {
  Eigen::MatrixX3d angles(faces.rows(), 3);
  for (Eigen::Index f = 0; f < faces.rows(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const Eigen::VectorXd at = points.row(faces(f, k));
      const Eigen::VectorXd to_next = Eigen::VectorXd(points.row(faces(f, (k + 1) % 3))) - at;
      const Eigen::VectorXd to_previous = Eigen::VectorXd(points.row(faces(f, (k + 2) % 3))) - at;
      angles(f, k) = std::acos(std::clamp(
          to_next.dot(to_previous) / (to_next.norm() * to_previous.norm()), -1.0, 1.0));
    }
  }
  return angles;
}

// Sum of the planar angles at each vertex of `loop` (the boundary), from per-face angles.
std::vector<double> angle_sums_at(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                  const std::vector<int>& loop) {
  std::vector<double> per_vertex(static_cast<std::size_t>(mesh.vertex_count()), 0.0);
  for (int f = 0; f < mesh.face_count(); ++f)
    for (int k = 0; k < 3; ++k) per_vertex[static_cast<std::size_t>(mesh.faces(f, k))] += angles(f, k);
  std::vector<double> sums;
  for (const int v : loop) sums.push_back(per_vertex[static_cast<std::size_t>(v)]);
  return sums;
}

// The mesh's boundary loop with the mesh on its left (faces are counter-clockwise).
std::vector<int> boundary_loop(const Mesh& mesh) {
  const std::vector<std::vector<int>> loops = boundary_loops(mesh);
  EXPECT_EQ(loops.size(), 1u);
  return loops.empty() ? std::vector<int>{} : loops.front();
}

// Turning angle of the UV polygon at each loop vertex (counter-clockwise positive): pi minus the
// interior angle there.
std::vector<double> turning_angles(const Eigen::MatrixX2d& uv, const std::vector<int>& loop) {
  std::vector<double> turning;
  const std::size_t n = loop.size();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector2d before = uv.row(loop[(i + n - 1) % n]);
    const Eigen::Vector2d at = uv.row(loop[i]);
    const Eigen::Vector2d after = uv.row(loop[(i + 1) % n]);
    const Eigen::Vector2d in = at - before, out = after - at;
    turning.push_back(std::atan2(in.x() * out.y() - in.y() * out.x(), in.dot(out)));
  }
  return turning;
}


// A flower-shaped disk: the planar disk pushed radially by 1 + 0.35 cos(5 theta) (five lobes,
// so its boundary has concave stretches) and bent out of the plane by a saddle z = 0.3 (x^2 - y^2).
// Classic ABF keeps the concave stretches; t = 1 must straighten them.
Mesh flower_disk(int rings = 6) {
  Mesh mesh = planar_disk(rings, 0.1);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const double x = mesh.vertices(v, 0), y = mesh.vertices(v, 1);
    const double radial = 1.0 + 0.35 * std::cos(5.0 * std::atan2(y, x)) * std::hypot(x, y);
    mesh.vertices(v, 0) = radial * x;
    mesh.vertices(v, 1) = radial * y;
    mesh.vertices(v, 2) = 0.3 * (x * x - y * y);
  }
  return mesh;
}

void expect_valid_map(const AngleMapResult& result, const std::string& name) {
  EXPECT_EQ(result.report.status, Status::ok) << name << ": " << result.report.message;
  EXPECT_LT(result.report.constraint_residual, 1e-8) << name;
  EXPECT_EQ(result.report.flipped_triangles, 0) << name;
  EXPECT_EQ(result.report.degenerate_triangles, 0) << name;
  EXPECT_EQ(result.report.boundary_self_intersections, 0) << name;
  EXPECT_TRUE(result.uv.allFinite()) << name;
}

AbfOptions cpu_options(AbfSolver solver = AbfSolver::automatic, double boundary_t = 2.0) {
  AbfOptions options;
  options.solver = solver;
  options.boundary_t = boundary_t;
  options.solver_options.backend = BackendChoice::cpu;
  return options;
}

TEST(Abf, ObtuseFanGivesAValidMap) {
  const Mesh mesh = obtuse_fan();
  const AngleMapResult result = abf(mesh, cpu_options());
  expect_valid_map(result, "obtuse fan");
  // The three central angles close the fan: they sum to 2 pi.
  double central = 0.0;
  for (int f = 0; f < 3; ++f) central += result.angles(f, 0);
  EXPECT_NEAR(central, 2.0 * kPi, 1e-9);
  EXPECT_GE(result.report.rounds, 1);
}

TEST(Abf, PlanarMeshIsReproducedUpToSimilarity) {
  const Mesh mesh = tilted_planar_disk(6, 0.3);
  const Eigen::MatrixX2d layout = planar_disk_layout(6, 0.3);
  const AngleMapResult result = abf(mesh, cpu_options());
  expect_valid_map(result, "tilted planar disk");
  const Eigen::MatrixX3d expected = mesh_angles(layout, mesh.faces);
  EXPECT_LT((result.angles - expected).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT(similarity_misfit(result.uv, layout), 1e-7);
  EXPECT_LT(result.abf_energy, 1e-14);
}

TEST(Abf, BoundaryControlOneGivesAConvexBoundary) {
  const Mesh mesh = flower_disk();
  const std::vector<int> loop = boundary_loop(mesh);
  const AngleMapResult classic = abf(mesh, cpu_options(AbfSolver::automatic, 2.0));
  expect_valid_map(classic, "flower, t = 2");
  const std::vector<double> classic_sums = angle_sums_at(mesh, classic.angles, loop);
  // Precondition: classic ABF keeps concave boundary vertices (angle sum above pi).
  ASSERT_GT(*std::max_element(classic_sums.begin(), classic_sums.end()), kPi + 0.1);

  const AngleMapResult convex = abf(mesh, cpu_options(AbfSolver::automatic, 1.0));
  expect_valid_map(convex, "flower, t = 1");
  for (const double sum : angle_sums_at(mesh, convex.angles, loop)) EXPECT_LE(sum, kPi + 1e-9);
  for (const double turning : turning_angles(convex.uv, loop)) EXPECT_GE(turning, -1e-9);
  // The constraint costs angle distortion.
  EXPECT_GT(convex.abf_energy, classic.abf_energy);
}

// alligator: a planar outline with legs and a long tail, 5,981 faces. Forcing its boundary convex
// folds the legs and tail inwards: angles are driven towards 0, and before the lower bounds of the
// angles the continuation stalled near t = 1.03.
// How far below its solved value the layout's turning at a boundary vertex may come from the
// least-squares reconstruction's rounding: its pinned system can be ill-conditioned (a condition
// number near 1e8 on the alligator at t = 1), and the rounding error that the condition number
// amplifies depends on the system's values and summation order, so it is measured, not assumed:
// the same angles are laid out again with another pair of pins (loop[0] and the vertex half way
// round), a system of the same kind whose rounding errors are independent of the first's, and
// the turnings of the two layouts compared (they are similarity invariant). Each layout's error is
// of the size of that difference; a margin of 10 covers a second one that happens to agree with
// the first.
double reconstruction_turning_tolerance(const Mesh& mesh, const AngleMapResult& result,
                                        const std::vector<int>& loop) {
  AnglesToUvOptions other_pins;
  other_pins.solver.backend = BackendChoice::cpu;
  other_pins.pin_first = loop.front();
  other_pins.pin_second = loop[loop.size() / 2];
  const MapResult again = angles_to_uv(mesh, result.angles, other_pins);
  EXPECT_TRUE(again.report.ok()) << again.report.message;
  const std::vector<double> first = turning_angles(result.uv, loop);
  const std::vector<double> second = turning_angles(again.uv, loop);
  double difference = 0.0;
  for (std::size_t i = 0; i < loop.size(); ++i)
    difference = std::max(difference, std::abs(first[i] - second[i]));
  return 10.0 * difference;
}

// (2.6) with t = 1: every boundary angle sum at most pi, so the layout's boundary is convex.
TEST(Abf, BoundaryControlOneConvergesOnTheAlligator) {
  const auto path = shared_data_dir() / "disk" / "alligator.obj";
  if (!std::filesystem::exists(path)) HARMONIA_SKIP_WITHOUT_CORPUS("no " << path);
  const Mesh mesh = read_mesh(path);
  const std::vector<int> loop = boundary_loop(mesh);
  const AbfOptions options = cpu_options(AbfSolver::automatic, 1.0);
  const AngleMapResult convex = abf(mesh, options);
  expect_valid_map(convex, "alligator, t = 1");
  EXPECT_EQ(convex.boundary_t, 1.0);
  // The solved angles meet the bound to the tolerance they were solved to, plus the rounding of
  // adding up at most 32 angles below pi.
  const double sum_rounding = 32.0 * std::numeric_limits<double>::epsilon() * kPi;
  for (const double sum : angle_sums_at(mesh, convex.angles, loop))
    EXPECT_LE(sum, kPi + options.constraint_tolerance + sum_rounding);
  // The layout's boundary: convex to within the reconstruction's accuracy.
  const double tolerance =
      options.constraint_tolerance + sum_rounding + reconstruction_turning_tolerance(mesh, convex, loop);
  const std::vector<double> turning = turning_angles(convex.uv, loop);
  for (std::size_t i = 0; i < loop.size(); ++i)
    EXPECT_GE(turning[i], -tolerance) << "boundary vertex " << loop[i];
}

// camel_b: 486 of its 2,032 vertices on the boundary, long legs. Convex ABF (t = 1) folds the
// legs in until dozens of angles sit on their lower bound; the iteration used to stall there
// ("no convergence in 100 Newton steps", violation 0.23): each continuation stage began with the
// wheel rows broken by log 2 (warm-start angles lifted off their bounds), and every angle heading
// for its bound cut the whole step. The turning angles are those of the solved angles, pi minus
// the angle sum: the legs shrink below 1e-14 of the area, where the layout cannot reproduce them.
TEST(Abf, BoundaryControlOneConvergesOnCamel) {
  const auto path = shared_data_dir() / "disk" / "camel_b.obj";
  if (!std::filesystem::exists(path)) HARMONIA_SKIP_WITHOUT_CORPUS("no " << path);
  const Mesh mesh = read_mesh(path);
  const std::vector<int> loop = boundary_loop(mesh);
  const AngleMapResult convex = abf(mesh, cpu_options(AbfSolver::automatic, 1.0));
  expect_valid_map(convex, "camel_b, t = 1");
  EXPECT_EQ(convex.boundary_t, 1.0);
  const std::vector<double> sums = angle_sums_at(mesh, convex.angles, loop);
  for (const double sum : sums) EXPECT_LE(sum, kPi + 1e-9);
  // Convex, and the bound is active somewhere (camel_b's classic layout is far from convex).
  EXPECT_NEAR(*std::max_element(sums.begin(), sums.end()), kPi, 1e-9);
  const Eigen::MatrixX3d targets = abf_target_angles(mesh);
  EXPECT_GE((convex.angles.array() / targets.array()).minCoeff(), 0.01 - 1e-12);
}

// (2.6) with t0 < t < 1 bounds every boundary angle sum by t pi < pi: every boundary vertex
// turns by at least (1 - t) pi, and since the turning angles add up to 2 pi (2.7) the polygon
// is pushed toward equal turning (t -> t0: a regular polygon's angles).
TEST(Abf, BoundaryControlBelowOneBoundsEveryTurningAngle) {
  const Mesh mesh = flower_disk();
  const std::vector<int> loop = boundary_loop(mesh);
  const double n = static_cast<double>(loop.size());
  const double t = 1.0 - 2.0 / n + 0.4 * (2.0 / n);  // Between t0 = 1 - 2/n and 1.
  const AngleMapResult result = abf(mesh, cpu_options(AbfSolver::automatic, t));
  expect_valid_map(result, "flower, t < 1");
  const std::vector<double> sums = angle_sums_at(mesh, result.angles, loop);
  for (const double sum : sums) EXPECT_LE(sum, t * kPi + 1e-9);
  for (const double turning : turning_angles(result.uv, loop))
    EXPECT_GE(turning, (1.0 - t) * kPi - 1e-6);
  // The rows are active where the 3D boundary wanted more: some sums sit on the bound.
  EXPECT_NEAR(*std::max_element(sums.begin(), sums.end()), t * kPi, 1e-8);
}

TEST(Abf, BoundaryControlTwoAndAboveIsClassicAbf) {
  for (const Mesh& mesh : {flower_disk(), hemisphere(6)}) {
    const std::vector<int> loop = boundary_loop(mesh);
    const AngleMapResult two = abf(mesh, cpu_options(AbfSolver::automatic, 2.0));
    const AngleMapResult hundred = abf(mesh, cpu_options(AbfSolver::automatic, 100.0));
    expect_valid_map(two, "t = 2");
    expect_valid_map(hundred, "t = 100");
    EXPECT_LT((two.angles - hundred.angles).cwiseAbs().maxCoeff(), 1e-9);
    EXPECT_EQ(two.report.rounds, hundred.report.rounds);
    // No boundary row is near its bound 2 pi, so none was active.
    const std::vector<double> sums = angle_sums_at(mesh, two.angles, loop);
    EXPECT_LT(*std::max_element(sums.begin(), sums.end()), 2.0 * kPi - 0.5);
  }
}

TEST(Abf, BoundaryControlAtOrBelowTheLowerBoundIsRejected) {
  const Mesh mesh = flower_disk();
  const int n = static_cast<int>(boundary_loop(mesh).size());
  for (const double t : {1.0 - 2.0 / n, 0.5, -1.0}) {
    const AngleMapResult result = abf(mesh, cpu_options(AbfSolver::automatic, t));
    EXPECT_EQ(result.report.status, Status::invalid_input) << t;
    EXPECT_NE(result.report.message.find("1 - 2/n"), std::string::npos) << result.report.message;
    EXPECT_NE(result.report.message.find("n = " + std::to_string(n)), std::string::npos)
        << result.report.message;
    EXPECT_EQ(result.uv.rows(), 0);
  }
  // Just above the bound is accepted.
  const AngleMapResult above = abf(mesh, cpu_options(AbfSolver::automatic, 1.0 - 1.9 / n));
  EXPECT_NE(above.report.status, Status::invalid_input) << above.report.message;
}

TEST(Abf, EverySolverReachesTheSameAngles) {
  const std::vector<AbfSolver> solvers = {AbfSolver::automatic,   AbfSolver::schur_direct,
                                          AbfSolver::schur_minres, AbfSolver::uzawa,
                                          AbfSolver::full_minres,  AbfSolver::full_cgnr};
  struct Case {
    std::string name;
    Mesh mesh;
    double t;
  };
  const std::vector<Case> cases = {{"spiked disk", spiked_disk(4, 1.5), 2.0},
                                   {"hemisphere", hemisphere(5), 2.0},
                                   {"flower, t = 1", flower_disk(4), 1.0}};
  for (const Case& c : cases) {
    const AngleMapResult reference = abf(c.mesh, cpu_options(AbfSolver::schur_direct, c.t));
    expect_valid_map(reference, c.name);
    for (const AbfSolver solver : solvers) {
      const AngleMapResult result = abf(c.mesh, cpu_options(solver, c.t));
      const std::string label = c.name + " / " + result.report.solver;
      expect_valid_map(result, label);
      EXPECT_LT((result.angles - reference.angles).cwiseAbs().maxCoeff(), 1e-6) << label;
      EXPECT_NEAR(result.abf_energy, reference.abf_energy, 1e-8 * (1.0 + reference.abf_energy))
          << label;
      EXPECT_LE(result.report.rounds, 20) << label;
    }
  }
}

TEST(Abf, UnderdeterminedVariantIsFeasibleAndValid) {
  for (const Mesh& mesh : {spiked_disk(5, 1.5), hemisphere(8), obtuse_fan()}) {
    AbfOptions options = cpu_options();
    const AngleMapResult minimum = abf(mesh, options);
    options.underdetermined = true;
    const AngleMapResult feasible = abf(mesh, options);
    expect_valid_map(feasible, "underdetermined");
    // The minimizer has the least energy of all feasible angle sets.
    EXPECT_GE(feasible.abf_energy, minimum.abf_energy - 1e-12);
  }
}

TEST(Abf, NonDiskIsRejectedPointingAtCut) {
  const AngleMapResult result = abf(tetrahedron(), cpu_options());
  EXPECT_EQ(result.report.status, Status::not_a_disk);
  EXPECT_NE(result.report.message.find("harmonia cut"), std::string::npos)
      << result.report.message;
}

TEST(Abf, SchurDirectIsRefusedWithoutADirectFactorization) {
  // The CPU backend has one: schur_direct runs there (the device case is in the Vulkan test).
  const AngleMapResult result = abf(hemisphere(4), cpu_options(AbfSolver::schur_direct));
  EXPECT_EQ(result.report.status, Status::ok) << result.report.message;
}

TEST(Abf, ProgressOncePerNewtonStepAndCancellation) {
  const Mesh mesh = spiked_disk(5, 1.5);
  AbfOptions options = cpu_options();
  std::vector<std::string> newton_stages;
  options.solver_options.progress = [&](const Progress& progress) {
    if (progress.stage.rfind("newton ", 0) == 0) newton_stages.emplace_back(progress.stage);
    return true;
  };
  const AngleMapResult result = abf(mesh, options);
  expect_valid_map(result, "spiked disk");
  ASSERT_GE(result.report.rounds, 1);
  EXPECT_EQ(static_cast<int>(newton_stages.size()), result.report.rounds);
  EXPECT_EQ(newton_stages.front().rfind("newton 1 (violation ", 0), 0u) << newton_stages.front();
  EXPECT_GT(result.abf_energy, 0.0);

  options.solver_options.progress = [](const Progress& progress) {
    return progress.stage.rfind("newton 2", 0) != 0;
  };
  const AngleMapResult cancelled = abf(mesh, options);
  EXPECT_EQ(cancelled.report.status, Status::cancelled);
  EXPECT_NE(cancelled.report.message.find("Newton step 2"), std::string::npos)
      << cancelled.report.message;
}

TEST(Abf, ReportCarriesTheSolveFigures) {
  const AngleMapResult result = abf(hemisphere(8), cpu_options(AbfSolver::schur_minres));
  expect_valid_map(result, "hemisphere");
  EXPECT_EQ(result.report.solver, "schur-minres");
  EXPECT_GT(result.report.iterations, 0);
  EXPECT_LE(result.report.residual, 1e-9);
  std::vector<std::string> phases;
  for (const PhaseTiming& timing : result.report.timings) phases.push_back(timing.phase);
  EXPECT_NE(std::find(phases.begin(), phases.end(), "newton"), phases.end());
  EXPECT_NE(std::find(phases.begin(), phases.end(), "setup"), phases.end());
  // The energy in the result is the objective (2.8) of its angles.
  EXPECT_NEAR(result.abf_energy, abf_energy(hemisphere(8), result.angles), 1e-12);
}

TEST(Abf, StoppedShortOfConvergenceItReturnsItsLastIterateAsAMap) {
  // Never nothing: with too few Newton steps the status says not_converged, and the angles of the
  // last iterate (inside (0, pi) by the step control) are laid out all the same.
  AbfOptions options = cpu_options();
  options.max_newton_iterations = 1;
  const Mesh mesh = hemisphere(8);
  const AngleMapResult result = abf(mesh, options);
  EXPECT_EQ(result.report.status, Status::not_converged) << result.report.message;
  EXPECT_NE(result.report.message.find("no convergence in 1 Newton steps"), std::string::npos)
      << result.report.message;
  ASSERT_EQ(result.uv.rows(), mesh.vertex_count());
  EXPECT_TRUE(result.uv.allFinite());
  EXPECT_GT(result.angles.minCoeff(), 0.0);
  EXPECT_LT(result.angles.maxCoeff(), std::numbers::pi);
  EXPECT_GT(result.report.constraint_residual, 0.0);
}

// Every corpus disk with the defaults (classic t = 2, avoid_boundary_crossings): no flips, no
// boundary self-intersection (camel_b's classic layout crosses itself; the ladder removes it).
TEST(Abf, EveryCorpusDiskIsValidWithSmallConstraintResidual) {
  const auto meshes = corpus_meshes("disk");
  if (meshes.empty()) HARMONIA_SKIP_WITHOUT_CORPUS("no corpus at " << shared_data_dir());
  for (const auto& path : meshes) {
    const std::string name = path.filename().string();
    const Mesh mesh = read_mesh(path);
    const AngleMapResult result = abf(mesh, cpu_options());
    expect_valid_map(result, name);
    std::printf("%-18s faces %6d t %.2f newton %2d constraint %.1e energy %.6g  %.3f s\n",
                name.c_str(), mesh.face_count(), result.boundary_t, result.report.rounds,
                result.report.constraint_residual, result.abf_energy,
                result.report.total_seconds());
  }
}


TEST(Abf, BoundaryCrossingAvoidanceOnAWoundStrip) {
  const Mesh mesh = wound_strip();
  AbfOptions plain = cpu_options();
  plain.avoid_boundary_crossings = false;
  const AngleMapResult crossing = abf(mesh, plain);
  EXPECT_EQ(crossing.report.status, Status::ok) << crossing.report.message;
  EXPECT_EQ(crossing.report.flipped_triangles, 0);
  EXPECT_GT(crossing.report.boundary_self_intersections, 0);
  EXPECT_EQ(crossing.boundary_t, 2.0);

  const AngleMapResult avoided = abf(mesh, cpu_options());
  expect_valid_map(avoided, "wound strip");
  EXPECT_LT(avoided.boundary_t, 2.0);
  const std::vector<int> loop = boundary_loop(mesh);
  for (const double sum : angle_sums_at(mesh, avoided.angles, loop))
    EXPECT_LE(sum, avoided.boundary_t * kPi + 1e-9);
  EXPECT_GT(avoided.abf_energy, crossing.abf_energy);
}

// cow-cut: a closed cow opened along one slit from end to end, with its legs, horns and tail
// left closed. The objective (2.8) charges at most 1 per angle driven to 0, and here its infimum
// pinches the legs with triangles whose angles vanish; the iteration used to crawl towards it and
// stop unconverged. With the lower bounds (1 % of the targets) it converges, some angles sit on
// their bound, and the map is valid although its legs shrink to below 1e-14 of the area.
TEST(Abf, CowCutConvergesWithAnglesHeldAtTheirLowerBound) {
  const auto path = shared_data_dir() / "disk" / "cow-cut.obj";
  if (!std::filesystem::exists(path)) HARMONIA_SKIP_WITHOUT_CORPUS("no " << path);
  const Mesh mesh = read_mesh(path);
  const AngleMapResult result = abf(mesh, cpu_options());
  expect_valid_map(result, "cow-cut");
  EXPECT_LT(result.report.constraint_residual, 1e-8);
  EXPECT_NE(result.report.message.find("less than 1e-14 of the total UV area"), std::string::npos)
      << result.report.message;
  const Eigen::MatrixX3d targets = abf_target_angles(mesh);
  const double smallest_ratio = (result.angles.array() / targets.array()).minCoeff();
  EXPECT_GE(smallest_ratio, 0.01);
  EXPECT_LT(smallest_ratio, 0.0101);  // The bound is active: the infimum lies below it.
}

#ifdef HARMONIA_HAVE_VULKAN
TEST(Abf, VulkanMatchesTheCpu) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  std::vector<std::pair<std::string, Mesh>> meshes = {{"hemisphere(8)", hemisphere(8)},
                                                      {"spiked disk", spiked_disk(5, 1.5)}};
  const std::filesystem::path woody = shared_data_dir() / "disk" / "woody.obj";
  if (std::filesystem::exists(woody)) meshes.emplace_back("woody", read_mesh(woody));
  for (const auto& [name, mesh] : meshes) {
    const AngleMapResult cpu = abf(mesh, cpu_options());
    for (const AbfSolver solver : {AbfSolver::automatic, AbfSolver::schur_minres,
                                   AbfSolver::uzawa}) {
      AbfOptions options;
      options.solver = solver;
      options.solver_options.backend = BackendChoice::vulkan;
      options.solver_options.vulkan_context = vulkan_test_context();
      const AngleMapResult gpu = abf(mesh, options);
      const std::string label = name + " / " + gpu.report.solver;
      EXPECT_EQ(gpu.report.status, Status::ok) << label << ": " << gpu.report.message;
      EXPECT_EQ(gpu.report.backend, BackendKind::vulkan) << label;
      EXPECT_EQ(gpu.report.flipped_triangles, cpu.report.flipped_triangles) << label;
      // The hemisphere's layout is rotationally symmetric, so the normalization's principal
      // axis (hence the rotation of the UVs) is not pinned down: compare up to a similarity, and
      // the angles directly.
      EXPECT_LT(similarity_misfit(gpu.uv, cpu.uv), 1e-4) << label;
      EXPECT_LT((gpu.angles - cpu.angles).cwiseAbs().maxCoeff(), 1e-5) << label;
      EXPECT_NEAR(gpu.abf_energy, cpu.abf_energy, 0.01 * cpu.abf_energy) << label;
    }
    AbfOptions direct;
    direct.solver = AbfSolver::schur_direct;
    direct.solver_options.backend = BackendChoice::vulkan;
    direct.solver_options.vulkan_context = vulkan_test_context();
    EXPECT_EQ(abf(mesh, direct).report.status, Status::unsupported) << name;
  }
}

// With the backend left to harmonia, a Newton step whose device solve fails (an iteration cap far
// too low) is solved again on the CPU, which takes the later steps too: the map is the CPU run's
// (Newton converged to the same tolerances), with a notice; asked for the device, ABF fails with
// the step's figures.
TEST(Abf, AnAutomaticChoiceSolvesTheStepsOnTheCpuWhereTheDeviceSolveFails) {
  HARMONIA_REQUIRE_VULKAN_TEST_DEVICE();
  const Mesh mesh = hemisphere(8);
  const AngleMapResult cpu = abf(mesh, cpu_options());
  ASSERT_TRUE(cpu.report.ok()) << cpu.report.message;
  AbfOptions options;
  options.solver_options.backend = BackendChoice::automatic;
  options.solver_options.vulkan_context = vulkan_test_context();
  options.solver_options.max_iterations = 2;
  const AngleMapResult automatic = abf(mesh, options);
  expect_moved_to_the_cpu(automatic.report);
  // The bounds of the device comparison above (VulkanMatchesTheCpu), which the CPU's own steps
  // meet a fortiori.
  EXPECT_LT(similarity_misfit(automatic.uv, cpu.uv), 1e-4);
  EXPECT_LT((automatic.angles - cpu.angles).cwiseAbs().maxCoeff(), 1e-5);

  options.solver_options.backend = BackendChoice::vulkan;
  expect_refused_with_figures(abf(mesh, options).report);
}
#endif

}  // namespace
}  // namespace harmonia::testing
