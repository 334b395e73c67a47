#pragma once
// The maps the concurrency tests run on several threads at once (tests/solve/test_concurrent_use.cpp
// on the CPU, tests/kernels/test_vulkan_concurrent_use.cpp on one shared Vulkan context), each with
// its own solver object, and the check that every thread got the serial result bit for bit.

#include <gtest/gtest.h>

#include <vector>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/linear_abf.h"
#include "harmonia/lscm.h"
#include "harmonia/quasi_harmonic_map.h"
#include "support/concurrent_runs.h"

namespace harmonia::testing {

using Layouts = std::vector<Eigen::MatrixX2d>;

//! A reusable mapper kept for two geometries: solve, bend the surface, solve again.
inline Layouts fixed_boundary_twice(const Mesh& mesh, const SolverOptions& solver) {
  FixedBoundaryOptions options;
  options.weights = WeightScheme::cotangent;
  options.solver = solver;
  FixedBoundaryMapper mapper(mesh, options);
  Layouts layouts{mapper.solve().uv};
  Eigen::MatrixX3d moved = mesh.vertices;
  moved.col(2) += 0.1 * moved.col(0).cwiseProduct(moved.col(1));
  mapper.update_geometry(moved);
  layouts.push_back(mapper.solve().uv);
  return layouts;
}

inline Layouts lscm_once(const Mesh& mesh, const SolverOptions& solver) {
  LscmOptions options;
  options.solver = solver;
  LscmSolver lscm_solver(mesh, options);
  return {lscm_solver.solve().uv};
}

inline Layouts quasi_harmonic_once(const Mesh& mesh, const SolverOptions& solver) {
  QuasiHarmonicOptions options;
  options.solver = solver;
  return {quasi_harmonic_map(mesh, options).uv};
}

inline Layouts linear_abf_once(const Mesh& mesh, const SolverOptions& solver) {
  LinearAbfOptions options;
  options.solver_options = solver;
  return {linear_abf(mesh, options).uv};
}

//! Every job gave finite layouts, and the same bits on its thread as serially.
inline void expect_serial_results(const SerialAndConcurrent<Layouts>& results) {
  ASSERT_EQ(results.concurrent.size(), results.serial.size());
  for (std::size_t job = 0; job < results.serial.size(); ++job) {
    ASSERT_EQ(results.concurrent[job].size(), results.serial[job].size()) << "job " << job;
    for (std::size_t k = 0; k < results.serial[job].size(); ++k) {
      const Eigen::MatrixX2d& serial = results.serial[job][k];
      const Eigen::MatrixX2d& concurrent = results.concurrent[job][k];
      ASSERT_GT(serial.rows(), 0) << "job " << job;
      ASSERT_TRUE(serial.allFinite()) << "job " << job;
      ASSERT_EQ(concurrent.rows(), serial.rows()) << "job " << job;
      EXPECT_TRUE(concurrent == serial) << "job " << job << ", layout " << k
                                        << ": largest difference "
                                        << (concurrent - serial).cwiseAbs().maxCoeff();
    }
  }
}

}  // namespace harmonia::testing
