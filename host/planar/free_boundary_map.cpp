// Free-boundary quasi-harmonic maps (thesis chapter 6, overall method of 6.4): P0 on a circle,
// then the boundary-free conformal map P1 (6.2) and the boundary-free quasi-harmonic map P2 (6.4),
// both Poisson equations over every vertex with a right-hand side gathered from the fragmented
// mesh, and the optional fixed-boundary polish P3.
//
// The Poisson problems. With S_T the element stiffness of triangle T and F_T its fragment, each
// step minimizes sum_T (grad u - grad F_T)^T C_T (grad u - grad F_T) |T|, whose normal equations
// are L u = sum_T S_T F_T: for P1 the cotangent stiffness of the 3D triangles (C = identity on the
// surface, the Laplacian of eq. 6.2 and of the fragmented mesh alike), for P2 the tensor-cotangent
// stiffness of P1's triangles with C from P1 (eq. 6.4 with the guidance field taken through C, so
// that both sides use one operator). The data sum to zero (every S_T has zero row and column sums),
// so the system is consistent with the null space of translations alone: the fragments' own
// orientations fix the rotation. One vertex, the first interior one, is held at the origin, which
// picks one solution of the singular system without changing the others; the layout is centred
// afterwards. Nothing on the boundary is pinned.
//
// Validity. Each step is taken in full only if its map is valid (no flipped or zero-area triangle,
// a simple boundary). Otherwise its fragments are reshaped by K^s with s < 1 (fragment_targets.h):
// s = 0 reproduces the step's start map exactly (the data are then the start map's own element
// loads), so a valid start gives a valid map for s small enough, and bisection on s finds the
// largest valid step. Each try costs a back-substitution (the operator does not depend on s).
//
// Where it runs. The operators (the cotangent Laplacian of P0 and P1, P2's tensor-cotangent
// operator) and P1's load (the surface's cotangent stiffness gathered from the fragments) are
// assembled through the backend (TriangleOperators, backend/backend.h): on the Vulkan backend by
// the device's triangle kernels, on the CPU by the host functions. The fragments themselves, the
// rotation field's angles and P2's load (the tensor stiffness of P1's layout, which no device
// kernel gathers) are computed on the host. P2's tensors C = K^-1 come from the stretches K that
// its fragments need anyway.

#include "harmonia/free_boundary_map.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <future>
#include <limits>
#include <sstream>
#include <string>
#include <utility>

#include "fallback/fragment_load.h"
#include "harmonia/laplacian.h"
#include "harmonia/metrics.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "mesh/power_of_two_scale.h"
#include "planar/boundary_crossings.h"
#include "planar/fragment_targets.h"
#include "planar/map_pipeline.h"
#include "mesh/helper_tasks.h"

namespace harmonia {
namespace {

struct Validity {
  int bad_triangles = 0;  // flipped + zero-area
  int boundary_crossings = 0;
  [[nodiscard]] int score() const { return bad_triangles + boundary_crossings; }
};

Validity validity_of(const Eigen::MatrixX2d& uv, const Mesh& mesh, const std::vector<int>& loop) {
  Validity validity;
  if (!uv.allFinite()) {
    validity.bad_triangles = static_cast<int>(mesh.faces.rows());
    return validity;
  }
  const FlipCount flips = count_flips(uv, mesh.faces);
  validity.bad_triangles = flips.flipped + flips.zero_area;
  validity.boundary_crossings = detail::count_loop_self_intersections(uv, loop);
  return validity;
}

std::string step_text(double step) {
  std::ostringstream text;
  text.precision(3);
  text << step;
  return text.str();
}

}  // namespace

struct FreeBoundaryMapper::Impl {
  Mesh mesh;           // The input scaled to unit size (mesh/power_of_two_scale.h) ...
  double scale = 1.0;  // ... by this power of two.
  FreeBoundaryOptions options;
  SolveReport setup;
  std::vector<int> loop;
  BoundaryPlacement placement;
  int held_vertex = 0;  // The vertex held at the origin in P1 and P2.
  std::unique_ptr<detail::Backend> backend;
  std::unique_ptr<detail::TriangleOperators> operators;  // Of mesh.faces, on the backend.
  Eigen::SparseMatrix<double> pattern;
  std::vector<int> vertex_ordering;
  // The boundary loop fixed: the cotangent system (P0 and the rotation fields) and, made when
  // needed, the mean-value one (P0 with mean-value weights or as the fall-back).
  std::unique_ptr<detail::DirichletSystem> circle_system;
  std::unique_ptr<detail::DirichletSystem> mean_value_system;
  std::unique_ptr<detail::DirichletSystem> poisson_system;  // P1, P2: one vertex held.
  std::unique_ptr<detail::FragmentRotationField> rotations;

  Impl(const Mesh& input, const FreeBoundaryOptions& free_options)
      : Impl(detail::unit_scaled(input), free_options) {}

  Impl(detail::ScaledMesh unit, const FreeBoundaryOptions& free_options)
      : mesh(std::move(unit.mesh)), scale(unit.scale), options(free_options) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    if (!detail::validate_mesh_arrays(mesh, setup)) return;
    std::future<detail::OperatorPattern> operator_pattern =
        detail::start_beside([this] { return detail::operator_pattern(mesh); });
    loop = detail::validate_disk_topology(mesh, setup);
    if (!setup.ok()) return;
    if (!validate_options()) return;
    if (!detail::validate_boundary_options(mesh, options.start_boundary, setup)) return;
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    if (!clock.start("analysis")) return;
    operators = backend->triangle_operators(mesh.faces, mesh.vertex_count());
    detail::OperatorPattern analyzed = operator_pattern.get();
    pattern = std::move(analyzed.pattern);
    vertex_ordering = std::move(analyzed.vertex_ordering);
    placement = place_boundary(mesh, loop, options.start_boundary);
    held_vertex = first_interior_vertex();
    if (options.rotation == FragmentRotation::least_squares_field)
      rotations = std::make_unique<detail::FragmentRotationField>(mesh);
    // The cotangent Laplacian's Dirichlet system on the circle: P0 (cotangent weights) and every
    // rotation field; P0 with mean-value weights has its own. A given start map with fragments in
    // their own frames needs neither.
    if (!has_start_map() || rotations)
      circle_system = make_circle_system(QuasiHarmonicWeights::tensor_cotangent);
    Eigen::VectorXi held(1);
    held[0] = held_vertex;
    poisson_system = std::make_unique<detail::DirichletSystem>(
        pattern, held, *backend, detail::MatrixKind::symmetric_positive_definite, options.solver,
        vertex_ordering);
  }

  [[nodiscard]] bool has_start_map() const { return options.start_uv.size() > 0; }

  // P0's Dirichlet system for the given weights (symmetric: Cholesky; mean value: LU).
  std::unique_ptr<detail::DirichletSystem> make_circle_system(QuasiHarmonicWeights weights) const {
    const detail::MatrixKind kind = weights == QuasiHarmonicWeights::tensor_cotangent
                                        ? detail::MatrixKind::symmetric_positive_definite
                                        : detail::MatrixKind::general;
    return std::make_unique<detail::DirichletSystem>(pattern, placement.vertices, *backend, kind,
                                                     options.solver, vertex_ordering);
  }

  // P0 (6.1): the fixed-boundary map on the circle with the chosen weights. Cotangent weights can
  // fold a mesh with obtuse triangles; the start of every later step must be valid, so a folded
  // cotangent start is replaced by the mean-value one (positive weights on a convex boundary:
  // valid by Tutte's theorem), reported in `fallbacks`.
  bool circle_map(const Eigen::SparseMatrix<double>& cotangent_laplacian, Eigen::MatrixX2d& start,
                  SolveReport& report) {
    const bool cotangent = options.weights == QuasiHarmonicWeights::tensor_cotangent;
    if (cotangent || rotations) {
      if (!circle_system->factorize(cotangent_laplacian, report)) return false;
      if (rotations) rotations->set_cotangent_weights(cotangent_laplacian);
    }
    if (cotangent) {
      if (!circle_system->solve(placement.uv, start, report)) return false;
      const Validity validity = validity_of(start, mesh, loop);
      if (validity.score() == 0) return true;
      report.fallbacks.push_back("P0 circle: mean-value weights (the cotangent map has " +
                                 std::to_string(validity.bad_triangles) +
                                 " flipped or zero-area triangles)");
    }
    if (!mean_value_system)
      mean_value_system = make_circle_system(QuasiHarmonicWeights::tensor_mean_value);
    return mean_value_system->factorize(laplacian(mesh, WeightScheme::mean_value), report) &&
           mean_value_system->solve(placement.uv, start, report);
  }

  bool validate_options() {
    const auto fail = [this](std::string message) {
      setup.status = Status::invalid_input;
      setup.message = "free-boundary map: " + std::move(message);
      return false;
    };
    if (options.step_bisections < 0 || options.step_bisections > 52)
      return fail("step_bisections must be in [0, 52]");
    if (options.polish && options.stop_after != FreeBoundaryStop::quasi_harmonic)
      return fail("polish needs stop_after = quasi_harmonic (P3 starts from P2)");
    if (options.conformal_rounds < 1 || options.conformal_rounds > 1000)
      return fail("conformal_rounds must be in [1, 1000]");
    if (has_start_map() && (options.start_uv.rows() != mesh.vertex_count() || !options.start_uv.allFinite()))
      return fail("start_uv must have one finite row per vertex (" + std::to_string(mesh.vertex_count()) +
                  "), got " + std::to_string(options.start_uv.rows()));
    return true;
  }

  // The smallest vertex index off the boundary (vertex 0 when every vertex is on it).
  int first_interior_vertex() const {
    std::vector<char> on_boundary(static_cast<std::size_t>(mesh.vertex_count()), 0);
    for (const int v : loop) on_boundary[static_cast<std::size_t>(v)] = 1;
    for (int v = 0; v < mesh.vertex_count(); ++v)
      if (!on_boundary[static_cast<std::size_t>(v)]) return v;
    return 0;
  }

  // One step of the pipeline taken as far as it stays valid: `attempt(s, uv)` computes the step's
  // map for the fraction s; `start` (the map at s = 0) is the fallback.
  bool valid_step(const std::string& name, const Eigen::MatrixX2d& start,
                  const std::function<bool(double, Eigen::MatrixX2d&)>& attempt,
                  FreeBoundaryStep& step, Eigen::MatrixX2d& result, SolveReport& report) {
    step.name = name;
    Eigen::MatrixX2d full;
    if (!attempt(1.0, full)) return false;
    const Validity full_validity = validity_of(full, mesh, loop);
    step.full_step_flips = full_validity.bad_triangles;
    step.full_step_boundary_intersections = full_validity.boundary_crossings;
    if (full_validity.score() == 0) {
      result = std::move(full);
      return true;
    }
    // Bisection between the start (s = 0) and the full step; keep the best map seen, preferring
    // the larger step among equally valid ones.
    double low = 0.0, high = 1.0;
    result = start;
    int best_score = validity_of(start, mesh, loop).score();
    double best_step = 0.0;
    if (full_validity.score() < best_score) {
      result = full;
      best_score = full_validity.score();
      best_step = 1.0;
    }
    for (int k = 0; k < options.step_bisections; ++k) {
      const double middle = 0.5 * (low + high);
      Eigen::MatrixX2d trial;
      if (!attempt(middle, trial)) return false;
      ++step.tries;
      const int score = validity_of(trial, mesh, loop).score();
      if (score == 0) low = middle; else high = middle;
      if (score < best_score || (score == best_score && middle > best_step)) {
        result = std::move(trial);
        best_score = score;
        best_step = middle;
      }
    }
    step.step = best_step;
    report.fallbacks.push_back(
        name + ": step shortened to " + step_text(best_step) + " (the full step has " +
        std::to_string(full_validity.bad_triangles) + " flipped or zero-area triangles and " +
        std::to_string(full_validity.boundary_crossings) + " boundary crossings)" +
        (best_score == 0 ? "" : "; no valid step found, the least invalid map is kept"));
    return true;
  }

  // The fragments of the layout uv for the step s: its triangles reshaped by K^s and turned by
  // the rotation field (or left in the thesis' frame of the layout), 3 #F by 2.
  bool fragments_of(const Eigen::MatrixX2d& uv, const detail::TriangleStretches& stretches,
                    double s, Eigen::MatrixXd& fragments, SolveReport& report) {
    const std::vector<Eigen::Matrix2d> shapes = stretches.powers(s);
    Eigen::VectorXd theta;
    if (rotations && !rotations->solve(uv, shapes, *circle_system, theta, report)) return false;
    fragments = detail::fragment_corners(mesh, uv, shapes, theta);
    return true;
  }

  FreeBoundaryResult solve() {
    FreeBoundaryResult result;
    result.report = setup;
    SolveReport& report = result.report;
    if (!report.ok()) return result;
    detail::PhaseClock clock(report, options.solver.progress);
    const Eigen::MatrixX2d held_origin = Eigen::MatrixX2d::Zero(1, 2);
    const auto timed = [&](FreeBoundaryStep& step, const std::chrono::steady_clock::time_point& begin) {
      step.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
      result.steps.push_back(step);
    };

    // P0: the fixed-boundary map on the circle (6.1). The surface's cotangent Laplacian (4.41) is
    // its operator (with cotangent weights), the rotation fields' and P1's.
    auto begin = std::chrono::steady_clock::now();
    if (!clock.start(has_start_map() ? "P1 conformal" : "P0 circle")) return result;
    const Eigen::SparseMatrix<double> cotangent_laplacian = operators->cotangent(mesh.vertices);
    Eigen::MatrixX2d start;
    if (has_start_map()) {
      // The caller's map in the unit-scaled mesh's lengths (the stretches compare it with them).
      start = options.start_uv * scale;
      if (rotations) {
        if (!circle_system->factorize(cotangent_laplacian, report)) return result;
        rotations->set_cotangent_weights(cotangent_laplacian);
      }
    } else {
      if (!circle_map(cotangent_laplacian, start, report)) return result;
      FreeBoundaryStep circle_step;
      circle_step.name = "P0 circle";
      timed(circle_step, begin);
      begin = std::chrono::steady_clock::now();
      if (!clock.start("P1 conformal")) return result;
    }

    // P1: the boundary-free conformal map (6.2), from the start map, then from each round's map.
    if (!poisson_system->factorize(cotangent_laplacian, report)) return result;
    Eigen::MatrixX2d conformal = start;
    for (int round = 0; round < options.conformal_rounds; ++round) {
      if (round > 0) begin = std::chrono::steady_clock::now();
      const Eigen::MatrixX2d round_start = std::move(conformal);
      const detail::TriangleStretches start_stretches = detail::triangle_stretches(mesh, round_start);
      // The load under the surface's own cotangent stiffness: the fragments are shaped toward the
      // 3D triangles.
      const auto conformal_attempt = [&](double s, Eigen::MatrixX2d& uv) {
        Eigen::MatrixXd fragments;
        if (!fragments_of(round_start, start_stretches, s, fragments, report)) return false;
        const Eigen::MatrixX2d load = operators->fragment_poisson_rhs(mesh.vertices, fragments);
        return poisson_system->solve(held_origin, load, uv, report);
      };
      FreeBoundaryStep conformal_step;
      const std::string name = round == 0 ? "P1 conformal" : "P1 round " + std::to_string(round + 1);
      if (!valid_step(name, round_start, conformal_attempt, conformal_step, conformal, report))
        return result;
      timed(conformal_step, begin);
      // No part of the step kept the map valid: later rounds would start from the same map.
      if (conformal_step.step == 0.0) break;
    }
    Eigen::MatrixX2d uv = conformal;

    // P2: the boundary-free quasi-harmonic map (6.4).
    if (options.stop_after == FreeBoundaryStop::quasi_harmonic) {
      begin = std::chrono::steady_clock::now();
      if (!clock.start("P2 quasi-harmonic")) return result;
      const detail::TriangleStretches stretches = detail::triangle_stretches(mesh, conformal);
      const TriangleTensors tensors = stretches.conductances(1.0);
      const detail::PairStiffness tensor_stiffness =
          detail::tensor_pair_stiffness(mesh, conformal, tensors);
      if (!poisson_system->factorize(operators->tensor_cotangent(conformal, tensors), report))
        return result;
      const auto quasi_harmonic_attempt = [&](double s, Eigen::MatrixX2d& next) {
        Eigen::MatrixXd fragments;
        if (!fragments_of(conformal, stretches, s, fragments, report)) return false;
        const Eigen::MatrixX2d load = detail::gather_fragment_load(
            mesh.faces, mesh.vertex_count(), tensor_stiffness, fragments);
        return poisson_system->solve(held_origin, load, next, report);
      };
      FreeBoundaryStep quasi_harmonic_step;
      if (!valid_step("P2 quasi-harmonic", conformal, quasi_harmonic_attempt, quasi_harmonic_step,
                      uv, report))
        return result;
      timed(quasi_harmonic_step, begin);

      // P3: the fixed-boundary quasi-harmonic polish with P2's boundary.
      if (options.polish) {
        begin = std::chrono::steady_clock::now();
        if (!clock.start("P3 polish")) return result;
        QuasiHarmonicOptions polish_options;
        polish_options.weights = options.weights;
        polish_options.initial = InitialMap::given;
        polish_options.initial_uv = uv;
        polish_options.max_rounds = 1;
        polish_options.solver = options.solver;
        polish_options.solver.progress = nullptr;
        polish_options.normalization = UvNormalization::none;
        QuasiHarmonicResult polished = quasi_harmonic_map(mesh, polish_options);
        report.iterations += polished.report.iterations;
        report.residual = std::max(report.residual, polished.report.residual);
        if (polished.uv.rows() != uv.rows()) {
          report.fallbacks.push_back("P3 polish: not taken (" + polished.report.message + ")");
        } else {
          const Eigen::MatrixX2d before = uv;
          const Eigen::MatrixX2d change = polished.uv - before;
          const auto polish_attempt = [&](double s, Eigen::MatrixX2d& next) {
            next = before + s * change;  // both share the boundary: a blend of the interiors
            return true;
          };
          FreeBoundaryStep polish_step;
          if (!valid_step("P3 polish", before, polish_attempt, polish_step, uv, report))
            return result;
          timed(polish_step, begin);
        }
      }
    }
    clock.stop();
    // Centre the raw layout on the held vertex's neighbours' frame: the centroid at the origin.
    uv.rowwise() -= uv.colwise().mean();
    report.cross_check_error = backend->cross_check_error();
    detail::finish_map(mesh, loop, options.normalization, uv, report, clock);
    detail::to_model_units(uv, scale, options.normalization, true);
    result.uv = std::move(uv);
    return result;
  }
};

FreeBoundaryMapper::FreeBoundaryMapper(const Mesh& mesh, const FreeBoundaryOptions& options)
    : impl_(std::make_unique<Impl>(mesh, options)) {}
FreeBoundaryMapper::~FreeBoundaryMapper() = default;
FreeBoundaryMapper::FreeBoundaryMapper(FreeBoundaryMapper&&) noexcept = default;
FreeBoundaryMapper& FreeBoundaryMapper::operator=(FreeBoundaryMapper&&) noexcept = default;

const SolveReport& FreeBoundaryMapper::setup_report() const { return impl_->setup; }

void FreeBoundaryMapper::update_geometry(const Eigen::MatrixX3d& vertices) {
  Impl& impl = *impl_;
  if (!impl.poisson_system) return;
  if (!detail::accept_new_geometry(impl.mesh, vertices, impl.setup)) return;
  impl.mesh.vertices = vertices * impl.scale;
  impl.placement = place_boundary(impl.mesh, impl.loop, impl.options.start_boundary);
}

FreeBoundaryResult FreeBoundaryMapper::solve() { return impl_->solve(); }

FreeBoundaryResult free_boundary_map(const Mesh& mesh, const FreeBoundaryOptions& options) {
  FreeBoundaryMapper mapper(mesh, options);
  return mapper.solve();
}

}  // namespace harmonia
