// The batched first round of linear ABF (abf/linear_abf_batch.h) on the CPU backend: several
// different disks in one block-diagonal PCG give, mesh by mesh, linear_abf()'s one-round angles
// within the bound the PCG tolerance and each reduced system's conditioning allow, and the same
// flips (none); a mesh that is not a disk gets its own error while the others succeed; rounds > 1
// and unfinished rounds are left to linear_abf().

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "abf/linear_abf_batch.h"
#include "fallback/cpu_backend.h"
#include "harmonia/io.h"
#include "harmonia/linear_abf.h"
#include "harmonia/procedural.h"
#include "harmonia/topology.h"
#include "support/angle_test_meshes.h"
#include "support/linear_abf_bounds.h"
#include "support/test_support.h"

namespace harmonia::testing {
namespace {

// Two triangles: a disk without interior vertices, whose reduced system is empty.
Mesh quad() {
  Mesh mesh;
  mesh.vertices.resize(4, 3);
  mesh.vertices << 0, 0, 0, 1, 0, 0.2, 1, 1, 0, 0, 1, 0.1;
  mesh.faces.resize(2, 3);
  mesh.faces << 0, 1, 2, 0, 2, 3;
  return mesh;
}

// A jittered planar disk bent into a bump: curved everywhere, irregular angles.
Mesh bumpy_disk() {
  Mesh mesh = planar_disk(7, 0.25);
  for (Eigen::Index v = 0; v < mesh.vertices.rows(); ++v) {
    const double x = mesh.vertices(v, 0), y = mesh.vertices(v, 1);
    mesh.vertices(v, 2) = 0.3 * std::sin(3.0 * x) * std::cos(2.0 * y);
  }
  return mesh;
}

// Different small disks: curved, planar and jittered (nothing to solve: its own angles meet the
// constraints), a large deficit, developable, no interior vertex (an empty block), and a curved
// corpus disk where the corpus is present.
std::vector<std::pair<std::string, Mesh>> disks() {
  std::vector<std::pair<std::string, Mesh>> meshes;
  meshes.emplace_back("hemisphere(8)", hemisphere(8));
  meshes.emplace_back("tilted planar disk", tilted_planar_disk());
  meshes.emplace_back("obtuse fan", obtuse_fan());
  meshes.emplace_back("spiked disk", spiked_disk(5, 0.6));
  meshes.emplace_back("developable strip", developable_strip(12, 5, 3.0, 1.0, 0.8));
  meshes.emplace_back("quad", quad());
  meshes.emplace_back("bumpy disk", bumpy_disk());
  const std::filesystem::path snail = shared_data_dir() / "disk" / "snail.obj";
  if (std::filesystem::exists(snail)) meshes.emplace_back("snail", read_mesh(snail));
  return meshes;
}

std::vector<const Mesh*> pointers(const std::vector<std::pair<std::string, Mesh>>& meshes) {
  std::vector<const Mesh*> list;
  for (const auto& entry : meshes) list.push_back(&entry.second);
  return list;
}

LinearAbfOptions one_round(double tolerance = SolverOptions{}.tolerance) {
  LinearAbfOptions options;
  options.rounds = 1;
  options.solver_options.backend = BackendChoice::cpu;
  options.solver_options.tolerance = tolerance;
  return options;
}

double angle_difference(const Eigen::MatrixX3d& a, const Eigen::MatrixX3d& b) {
  return (a - b).norm();
}

TEST(LinearAbfBatch, MatchesLinearAbfMeshByMesh) {
  const auto meshes = disks();
  // The default tolerance, and one loose enough that the PCG's error is far above rounding: the
  // bound must follow it.
  for (const double tolerance : {SolverOptions{}.tolerance, 1e-6}) {
    const LinearAbfOptions options = one_round(tolerance);
    detail::CpuBackend cpu;
    const std::vector<AngleMapResult> batch =
        detail::linear_abf_batch(pointers(meshes), options, cpu, 2);
    const std::vector<std::optional<AngleMapResult>> first =
        detail::linear_abf_first_rounds(pointers(meshes), options, cpu, 1);
    ASSERT_EQ(batch.size(), meshes.size());
    for (std::size_t i = 0; i < meshes.size(); ++i) {
      const auto& [name, mesh] = meshes[i];
      SCOPED_TRACE(name + ", tolerance " + std::to_string(tolerance));
      const AngleMapResult single = linear_abf(mesh, options);
      ASSERT_TRUE(single.report.ok()) << single.report.message;
      ASSERT_EQ(single.report.rounds, 1);
      // Every one of these disks is a valid map after one round: the batch's result is final.
      ASSERT_TRUE(first[i].has_value());
      const AngleMapResult& result = batch[i];
      ASSERT_TRUE(result.report.ok()) << result.report.message;
      EXPECT_EQ(result.report.rounds, 1);
      EXPECT_NE(result.report.solver.find("block-pcg"), std::string::npos) << result.report.solver;
      EXPECT_NE(result.report.solver.find(std::to_string(meshes.size()) + " meshes"),
                std::string::npos)
          << result.report.solver;
      EXPECT_LE(result.report.residual, std::max(tolerance, single.report.residual));
      ASSERT_EQ(result.angles.rows(), mesh.faces.rows());
      const double bound = first_round_angle_bound(mesh, tolerance);
      EXPECT_LE(angle_difference(result.angles, single.angles), bound);
      // The threads do not change a bit.
      EXPECT_EQ(angle_difference(result.angles, first[i]->angles), 0.0);
      EXPECT_EQ(result.report.flipped_triangles, 0);
      EXPECT_EQ(result.report.flipped_triangles, single.report.flipped_triangles);
      EXPECT_EQ(result.report.degenerate_triangles, 0);
      EXPECT_EQ(result.report.boundary_self_intersections, 0);
      EXPECT_EQ(result.uv.rows(), mesh.vertices.rows());
      // The same energy and constraint violation up to what the angles' difference moves them.
      EXPECT_NEAR(result.report.constraint_residual, single.report.constraint_residual,
                  1e-6 + 1e3 * bound);
      EXPECT_NEAR(result.abf_energy, single.abf_energy,
                  1e-12 + 1e3 * bound * (1.0 + single.abf_energy));
    }
  }
}

TEST(LinearAbfBatch, AMeshThatIsNotADiskFailsAlone) {
  auto meshes = disks();
  meshes.insert(meshes.begin() + 2, {"sphere", unit_sphere(1)});
  meshes.emplace_back("tetrahedron", tetrahedron());
  const LinearAbfOptions options = one_round();
  detail::CpuBackend cpu;
  const std::vector<AngleMapResult> batch =
      detail::linear_abf_batch(pointers(meshes), options, cpu);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    const auto& [name, mesh] = meshes[i];
    SCOPED_TRACE(name);
    const AngleMapResult single = linear_abf(mesh, options);
    EXPECT_EQ(batch[i].report.status, single.report.status);
    EXPECT_EQ(batch[i].report.message, single.report.message);
    if (name == "sphere" || name == "tetrahedron") {
      EXPECT_EQ(batch[i].report.status, Status::not_a_disk) << batch[i].report.message;
      EXPECT_EQ(batch[i].uv.rows(), 0);
    } else {
      ASSERT_TRUE(batch[i].report.ok()) << batch[i].report.message;
      // The disks share the one solve: the refused meshes have no block.
      EXPECT_NE(batch[i].report.solver.find(std::to_string(meshes.size() - 2) + " meshes"),
                std::string::npos)
          << batch[i].report.solver;
      EXPECT_LE(angle_difference(batch[i].angles, single.angles),
                first_round_angle_bound(mesh, options.solver_options.tolerance));
    }
  }
}

// The wound strip's first round crosses its boundary: linear_abf() goes on with boundary rounds,
// so its batched round is not final, and the batch's result is linear_abf()'s own. Without
// avoid_boundary_crossings, linear_abf() stops after that round, and so does the batch.
TEST(LinearAbfBatch, ARoundThatIsNotFinalIsLinearAbfs) {
  std::vector<std::pair<std::string, Mesh>> meshes;
  meshes.emplace_back("hemisphere(8)", hemisphere(8));
  meshes.emplace_back("wound strip", wound_strip());
  meshes.emplace_back("spiked disk", spiked_disk(5, 0.6));
  LinearAbfOptions options = one_round();
  detail::CpuBackend cpu;
  const auto first = detail::linear_abf_first_rounds(pointers(meshes), options, cpu);
  EXPECT_TRUE(first[0].has_value());
  EXPECT_FALSE(first[1].has_value());
  EXPECT_TRUE(first[2].has_value());
  const std::vector<AngleMapResult> batch =
      detail::linear_abf_batch(pointers(meshes), options, cpu);
  const AngleMapResult single = linear_abf(meshes[1].second, options);
  ASSERT_TRUE(batch[1].report.ok()) << batch[1].report.message;
  EXPECT_GT(batch[1].report.rounds, 1);
  EXPECT_EQ(batch[1].report.rounds, single.report.rounds);
  EXPECT_EQ(batch[1].report.solver, single.report.solver);
  EXPECT_EQ(batch[1].boundary_t, single.boundary_t);
  EXPECT_EQ(batch[1].report.boundary_self_intersections, 0);
  EXPECT_EQ(angle_difference(batch[1].angles, single.angles), 0.0);

  options.avoid_boundary_crossings = false;
  const auto crossing = detail::linear_abf_first_rounds(pointers(meshes), options, cpu);
  ASSERT_TRUE(crossing[1].has_value());
  const AngleMapResult plain = linear_abf(meshes[1].second, options);
  EXPECT_EQ(crossing[1]->report.rounds, 1);
  EXPECT_GT(crossing[1]->report.boundary_self_intersections, 0);
  EXPECT_EQ(crossing[1]->report.boundary_self_intersections,
            plain.report.boundary_self_intersections);
  EXPECT_LE(angle_difference(crossing[1]->angles, plain.angles),
            first_round_angle_bound(meshes[1].second, options.solver_options.tolerance));
}

TEST(LinearAbfBatch, InvalidOptionsAreReportedPerMesh) {
  const auto meshes = disks();
  LinearAbfOptions options = one_round();
  options.rounds = -1;
  detail::CpuBackend cpu;
  const std::vector<AngleMapResult> batch =
      detail::linear_abf_batch(pointers(meshes), options, cpu);
  for (const AngleMapResult& result : batch) {
    EXPECT_EQ(result.report.status, Status::invalid_input);
    EXPECT_NE(result.report.message.find("rounds"), std::string::npos) << result.report.message;
  }
}

// Several rounds are linear_abf()'s own: nothing is batched, and the results are its own.
TEST(LinearAbfBatch, SeveralRoundsAreLeftToLinearAbf) {
  const auto meshes = disks();
  LinearAbfOptions options = one_round();
  options.rounds = 2;
  detail::CpuBackend cpu;
  for (const auto& first : detail::linear_abf_first_rounds(pointers(meshes), options, cpu))
    EXPECT_FALSE(first.has_value());
  const std::vector<AngleMapResult> batch =
      detail::linear_abf_batch(pointers(meshes), options, cpu);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    SCOPED_TRACE(meshes[i].first);
    const AngleMapResult single = linear_abf(meshes[i].second, options);
    EXPECT_EQ(batch[i].report.rounds, single.report.rounds);
    EXPECT_EQ(batch[i].report.solver, single.report.solver);
    EXPECT_EQ(angle_difference(batch[i].angles, single.angles), 0.0);
  }
}

// The automatic mode stops after a first round that is a valid map, so the batch serves it too,
// with the same angles as rounds = 1.
TEST(LinearAbfBatch, AutomaticRoundsBatchTheFirstRound) {
  const auto meshes = disks();
  LinearAbfOptions options = one_round();
  detail::CpuBackend cpu;
  const std::vector<AngleMapResult> once = detail::linear_abf_batch(pointers(meshes), options, cpu);
  options.rounds = 0;
  const std::vector<AngleMapResult> automatic =
      detail::linear_abf_batch(pointers(meshes), options, cpu);
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    SCOPED_TRACE(meshes[i].first);
    ASSERT_TRUE(automatic[i].report.ok()) << automatic[i].report.message;
    EXPECT_EQ(automatic[i].report.rounds, 1);
    EXPECT_EQ(angle_difference(automatic[i].angles, once[i].angles), 0.0);
  }
}

TEST(LinearAbfBatch, NoMeshesNoResults) {
  detail::CpuBackend cpu;
  EXPECT_TRUE(detail::linear_abf_batch({}, one_round(), cpu).empty());
}

}  // namespace
}  // namespace harmonia::testing
