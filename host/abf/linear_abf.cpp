// Linear angle based flattening (thesis chapter 3). Around an estimate alpha of the planar angles,
// the angle constraints are linear in the error e = alpha* - alpha up to terms quadratic in e
// (3.2, 3.3, 3.7): A e = b with A = J(alpha), the Jacobian of the constraints in their log-sine
// form, and b = -h(alpha). The error of least weighted norm, min sum (e / alpha)^2 (3.9), is
// e = W A^T (A W A^T)^-1 b with W = diag(alpha^2) (3.12-3.13, with C = A D_alpha): one
// saddle-point solve, done with the triangle rows eliminated (abf/reduced_angle_system.h).
// The angles alpha + e become UVs through angles_to_uv().
//
// Later rounds relinearize at the previous result, clamped into (0, pi). A round after a valid
// one is the thesis' problem around that result (a Newton projection onto the exact
// constraints). A round after an invalid one is anchored: it keeps the first round's objective
// (3.9), the distance to the first estimate alpha_0, and only moves the linearization point:
//     min sum ((alpha_k + e - alpha_0) / alpha_0)^2  s.t.  J(alpha_k) e = -h(alpha_k),
// with alpha_k the clamped previous result: a Gauss-Newton step on the first round's problem,
// solved like (3.10-3.13) (W = alpha_0^2, r = (alpha_0 - alpha_k) / alpha_0^2 in
// ReducedAngleSystem's notation). Clamping moves the angles far from any solution
// of that problem, and a least-norm round around the clamped angles would measure the distance
// to them instead (cow-cut: ABF energy 710 against 627 anchored; nonlinear ABF: 620).

#include "harmonia/linear_abf.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <future>
#include <memory>
#include <numbers>
#include <string>
#include <utility>

#include "abf/abf_newton.h"
#include "abf/angle_constraints.h"
#include "abf/linear_abf_estimate.h"
#include "abf/linear_abf_round.h"
#include "abf/reduced_angle_system.h"
#include "abf/validated_angles_to_uv.h"
#include "fallback/separator_first_ordering.h"
#include "mesh/power_of_two_scale.h"
#include "planar/map_pipeline.h"
#include "solve/backend_selection.h"
#include "mesh/helper_tasks.h"

namespace harmonia {
namespace {

// Rounds at the convex boundary control t = 1 before the boundary rounds give up.
constexpr int kConvexRounds = 3;
// Automatic mode: the most linearization rounds, and the largest violation of the exact angle
// constraints (radians; log-sine units for the wheel) at which rounds after a first round that
// was not a valid map stop. Rounds after valid angles are Newton projections and converge
// quadratically: cow-cut needs 6 (violation 3.3, 0.70, 0.067, ..., 3e-8) to reach the energy of
// ABF within 3 %, where 2 rounds left it 75 % above.
constexpr int kAutomaticRounds = 8;
constexpr double kConvergedViolation = 1e-6;

// Linear ABF of a mesh already scaled to unit size (linear_abf() below scales it).
AngleMapResult linear_abf_at_unit_size(const Mesh& mesh, const LinearAbfOptions& options) {
  AngleMapResult result;
  SolveReport& report = result.report;
  const ProgressCallback& progress = options.solver_options.progress;
  detail::PhaseClock clock(report, progress);
  if (!clock.start("validation")) return result;
  if (!detail::validate_linear_abf_options(options, report)) return result;
  if (!detail::validate_mesh_arrays(mesh, report)) return result;
  // One fill-reducing ordering of the vertices serves the reduced angle system (restricted to
  // the vertices owning rows) and the reconstruction: computed from the faces alone on a second
  // thread while this one validates, estimates and assembles (the result does not depend on the
  // timing).
  // The ordering comes top separator first (separator_first_ordering.h): the first round's
  // factorization starts on side 0 while METIS still orders side 1.
  detail::SeparatorFirstOrdering staged_ordering;
  std::future<void> ordering_task = detail::start_beside([&mesh, &staged_ordering] {
    staged_ordering.compute(mesh.faces, mesh.vertex_count());
  });
  std::vector<int> vertex_ordering;
  bool ordering_ready = false;
  const auto take_vertex_ordering = [&]() -> const std::vector<int>& {
    if (!ordering_ready) vertex_ordering = staged_ordering.vertex_ordering();
    ordering_ready = true;
    return vertex_ordering;
  };
  const std::vector<int> loop = detail::validate_disk_topology(mesh, report);
  if (!report.ok()) return result;
  std::unique_ptr<detail::Backend> backend = detail::choose_backend(options.solver_options, report);
  if (!backend) return result;

  if (!clock.start("estimate")) return result;
  const detail::AngleTopology topology = detail::build_angle_topology(mesh, loop);
  const Eigen::VectorXd spatial = detail::corner_angles(mesh);
  Eigen::VectorXd estimate =
      detail::linear_abf_estimate(mesh, topology, spatial, options.exponential_map_deficit);

  detail::IterativeSettings settings;
  settings.relative_tolerance = options.solver_options.tolerance;
  settings.max_iterations = options.solver_options.max_iterations;
  // Created per round and released before the reconstruction, which needs memory of the same
  // order for its own factorization.
  std::unique_ptr<detail::ReducedAngleSystem> system;
  const int max_rounds = options.rounds > 0 ? options.rounds : kAutomaticRounds;
  Eigen::VectorXd angles;
  MapResult layout;
  AnglesToUvOptions reconstruction = options.reconstruction;
  reconstruction.solver = options.solver_options;
  int rounds_done = 0;
  std::string moved_from_device_solver;  // The device's solver, once the rounds moved to the CPU.
  // The reconstruction is set up while the ordering is computed (its pattern depends on the mesh
  // alone) and analyzed for the estimate's angles during the reduced system's factorization, on
  // the thread that waits there for the second half (ReducedAngleSystem::factorize's
  // `meanwhile`): its pattern is the final angles' but for needle-thin faces, where the
  // reconstruction analyzes again.
  std::unique_ptr<detail::PreparedLayout> prepared_layout;
  bool layout_prepared = false;
  std::function<void()> layout_analysis;  // Pending until run.
  const auto prepare_layout = [&](const Eigen::VectorXd& predicted_angles) {
    if (layout_prepared) return;
    layout_prepared = true;
    prepared_layout = detail::prepare_layout(mesh, reconstruction, loop);
    if (!prepared_layout) return;
    layout_analysis = [&staged_ordering, layout = prepared_layout.get(),
                       predicted = detail::corner_rows(detail::clamp_angles(predicted_angles))] {
      layout->system->set_vertex_ordering(staged_ordering.vertex_ordering());
      layout->system->analyze(predicted);
    };
    if (!prepared_layout->overlappable) std::exchange(layout_analysis, {})();
  };
  // The angles' constraint residual and ABF energy, for the report: computed on a second thread
  // while the angles are laid out (most of the reconstruction runs on one), kept if they are the
  // final angles.
  const auto summarize = [&topology, &spatial](const Eigen::VectorXd& summarized) {
    return detail::summarize_linear_abf_angles(topology, spatial, summarized);
  };
  Eigen::VectorXd summarized_angles;
  std::future<detail::LinearAbfAngleSummary> summary;
  // The angles are valid (in (0, pi)) wherever this is called and the mesh a validated disk.
  const auto reconstruct = [&](const Eigen::VectorXd& valid_angles) {
    if (summary.valid()) summary.wait();  // Its angles may be about to change.
    summarized_angles = valid_angles;
    summary = detail::start_beside([&] { return summarize(summarized_angles); });
    if (layout_analysis) std::exchange(layout_analysis, {})();
    return detail::angles_to_uv_validated(mesh, detail::corner_rows(valid_angles), reconstruction,
                                          {loop, take_vertex_ordering(), prepared_layout.get()});
  };
  // The centre of an anchored round's objective.
  const Eigen::VectorXd first_estimate = estimate;
  // One linearization round around `estimate` with the boundary rows (2.6) of `boundary_rows`
  // (vertices) at `boundary_t`, anchored at the first estimate or not; false when its solve
  // failed (the report says why).
  const auto run_round = [&](const std::vector<int>& boundary_rows, double boundary_t,
                             bool anchored, int planned) {
    if (!clock.start("assembly", rounds_done, planned)) return false;
    // The least-norm problem (3.9) around its own estimate (3.4.: "the angles computed at one
    // iteration are constrained in [0, pi] and define the alphas of the next"), or anchored at
    // the first estimate (see the top of this file): linear_abf_round.h writes it out.
    const detail::LinearizedRound linearized = detail::linearize_round(
        topology, estimate, anchored ? first_estimate : estimate, boundary_rows, boundary_t);
    const detail::AngleConstraints& constraints = linearized.constraints;
    // The reduced system's factorization and solve; false when the clock stopped them.
    detail::SolveStats stats;
    const auto solve_round = [&](bool first_try) {
      system = std::make_unique<detail::ReducedAngleSystem>(*backend, topology, settings, progress);
      system->assemble(constraints.jacobian, linearized.weights);
      prepare_layout(estimate);
      if (rounds_done == 0 && first_try)
        system->use_vertex_ordering(staged_ordering);
      else
        system->use_vertex_ordering(take_vertex_ordering());
      if (!clock.start("factorization", rounds_done, planned)) return false;
      stats = system->factorize(std::exchange(layout_analysis, {}));
      if (stats.status == Status::ok) {
        if (!clock.start("solve", rounds_done, planned)) return false;
        Eigen::VectorXd error, multipliers;
        // e = W (r - A^T x) with (A W A^T) x = A W r - b; for r = 0, (3.12-3.13).
        stats = system->solve_assembled(linearized.pull, -constraints.values, error, multipliers);
        angles = estimate + error;  // (3.1)
      }
      return true;
    };
    if (!solve_round(true)) return false;
    // A device solve that failed where the backend was left to harmonia: this round and the
    // ones after it on the CPU (solve/backend_selection.h).
    if (!detail::linear_abf_solve_accepted(stats.status, stats.relative_residual) &&
        detail::may_retry_on_cpu(options.solver_options.backend, *backend, stats)) {
      const std::string device_solver = system->solver_name();
      const detail::SolveStats failed = stats;
      report.iterations += stats.iterations;
      backend = detail::make_backend(BackendChoice::cpu, nullptr);
      if (!solve_round(false)) return false;
      if (stats.status == Status::ok) {
        report.fallbacks.push_back(detail::cpu_retry_notice(device_solver, failed, *backend));
        moved_from_device_solver = device_solver;
      }
    }
    report.rounds = ++rounds_done;
    report.iterations += stats.iterations;
    report.residual = std::max(report.residual, stats.relative_residual);
    report.solver = system->solver_name() + (moved_from_device_solver.empty()
                                                 ? std::string()
                                                 : " (after the device's " + moved_from_device_solver + " failed)");
    system.reset();
    // A device solve that stalled just above the requested tolerance is accepted, with the
    // residual reached in the report (linear_abf_round.h).
    if (!detail::linear_abf_solve_accepted(stats.status, stats.relative_residual)) {
      report.status = stats.status;
      report.message = "linear_abf: round " + std::to_string(rounds_done) + ": " + stats.message;
      report.cross_check_error = backend->cross_check_error();
      return false;
    }
    if (detail::first_invalid_corner(angles) < 0) {
      if (!clock.start("reconstruction", rounds_done, planned)) return false;
      layout = reconstruct(angles);
    }
    return true;
  };
  bool anchored = false;  // The first round is centred at the first estimate anyway.
  // Automatic mode: one round when it gives a valid map (one linearization is enough). When it
  // does not, the problem is far from linear there, and rounds go on until the angles are a
  // valid map that meets the exact constraints (kConvergedViolation).
  bool far_from_linear = false;
  for (int round = 0; round < max_rounds; ++round) {
    if (!run_round({}, 2.0, anchored, max_rounds)) return result;
    const bool valid_angles = detail::first_invalid_corner(angles) < 0;
    const bool last = round + 1 == max_rounds;
    const bool good = valid_angles && layout.report.ok();
    if (last) break;
    if (options.rounds == 0) {
      if (!good) {
        far_from_linear = true;
      } else if (!far_from_linear ||
                 detail::angle_constraint_values(topology, angles).lpNorm<Eigen::Infinity>() <=
                     kConvergedViolation) {
        break;
      }
    }
    estimate = detail::clamp_angles(angles);  // The next round's estimate.
    // Anchored after invalid angles only: rounds after valid ones converge quadratically to the
    // exact constraints, anchored rounds only linearly (and on cow-cut not at all: the
    // constraints' curvature, which the linearization drops, outweighs the objective's).
    anchored = !valid_angles;
  }

  // Boundary control (2.6) when the layout's boundary crosses itself: further rounds that add
  // the linearized row of every boundary vertex whose angle sum exceeds t pi, for t on the
  // ladder 1.5, 1.25, 1 (and a few more rounds at t = 1, where vertices that the previous rows
  // pushed over the bound get theirs). Rows of earlier rounds stay (at the new t). Never all
  // rows: with every boundary sum fixed at t pi they would contradict the total pi (n - 2) (2.7).
  // They follow valid angles, so they are not anchored: the new rows are met by the nearest
  // change of the current angles.
  const std::size_t boundary_count = topology.boundary_vertices.size();
  std::vector<bool> has_row(boundary_count, false);
  std::size_t row_count = 0;
  int rounds_at_convex = 0;
  while (options.avoid_boundary_crossings && detail::first_invalid_corner(angles) < 0 &&
         layout.report.boundary_self_intersections > 0 && rounds_at_convex < kConvexRounds) {
    result.boundary_t = std::max(1.0, result.boundary_t > 0.0 ? result.boundary_t - 0.25 : 1.5);
    if (result.boundary_t == 1.0) ++rounds_at_convex;
    estimate = detail::clamp_angles(angles);
    const Eigen::VectorXd sums = detail::boundary_angle_sums(topology, estimate);
    bool added = false;
    for (std::size_t b = 0; b < boundary_count; ++b) {
      if (has_row[b] || row_count + 1 >= boundary_count) continue;
      if (sums[static_cast<Eigen::Index>(b)] > result.boundary_t * std::numbers::pi) {
        has_row[b] = true;
        ++row_count;
        added = true;
      }
    }
    if (!added && result.boundary_t == 1.0 && rounds_at_convex > 1) break;
    std::vector<int> rows;  // Loop order.
    for (std::size_t b = 0; b < boundary_count; ++b)
      if (has_row[b]) rows.push_back(topology.boundary_vertices[b]);
    if (!run_round(rows, result.boundary_t, false, rounds_done + 1)) return result;
  }

  const int invalid = detail::first_invalid_corner(angles);
  if (invalid >= 0) {
    // Still invalid after the last round: lay out the angles clamped into (0, pi), and say so.
    angles = detail::clamp_angles(angles);
    if (!clock.start("reconstruction")) return result;
    layout = reconstruct(angles);
  }
  clock.stop();
  const detail::LinearAbfAngleSummary final_summary =
      summary.valid() && summarized_angles.size() == angles.size() && summarized_angles == angles
          ? summary.get()
          : summarize(angles);
  detail::finish_linear_abf_result(angles, std::move(layout), final_summary, invalid,
                                   backend->cross_check_error(), result);
  return result;
}

}  // namespace

AngleMapResult linear_abf(const Mesh& mesh, const LinearAbfOptions& options) {
  // Computed on the mesh scaled to unit size (mesh/power_of_two_scale.h): its 3D angles, areas and
  // tolerances do not depend on the model's units; the layout comes back in them.
  const detail::ScaledMesh unit = detail::unit_scaled(mesh);
  AngleMapResult result = linear_abf_at_unit_size(unit.mesh, options);
  detail::to_model_units(result.uv, unit.scale, options.reconstruction.normalization, true);
  return result;
}

}  // namespace harmonia
