// Quasi-harmonic maps (thesis chapter 5, steps 1-5): from a start map, estimate per triangle the
// planar Jacobian K = sqrt(I) that would reproduce the surface's first fundamental form I, and
// solve div(K^-1 grad f) = 0 (eq. 5.8, discretized by eq. 5.10 or section 5.4) with the start map's
// boundary. Repeating from the new map self-corrects a poor start; 3-5 rounds usually suffice.
//
// Regularization (documented behaviour): a triangle whose current UV area is zero (|area| below
// 1e-12 of the mean) or whose tensor is not finite has no usable Jacobian. Such a triangle
// contributes the plain 3D cotangent weights instead, i.e. the weights it would have if it were
// already laid out isometrically (C = identity on its isometric layout). So degenerate starts
// never produce NaN, and one round moves the triangle away from degeneracy.

#include "harmonia/quasi_harmonic_map.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <future>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "harmonia/laplacian.h"
#include "harmonia/metrics.h"
#include "harmonia/quasi_harmonic_operator.h"
#include "mesh/power_of_two_scale.h"
#include "planar/map_pipeline.h"
#include "mesh/helper_tasks.h"

namespace harmonia {
namespace {

double uv_signed_area(const Eigen::MatrixX2d& uv, const Eigen::Vector3i& face) {
  const Eigen::Vector2d e1 = uv.row(face[1]) - uv.row(face[0]),
                        e2 = uv.row(face[2]) - uv.row(face[0]);
  return 0.5 * (e1.x() * e2.y() - e1.y() * e2.x());
}

// The quasi-harmonic operator of the current map, with the regularization described above.
Eigen::SparseMatrix<double> quasi_harmonic_operator(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                                                    QuasiHarmonicWeights weights) {
  const TriangleTensors tensors = quasi_harmonic_tensors(mesh, uv);
  const int face_count = mesh.face_count();
  double mean_area = 0.0;
  for (int f = 0; f < face_count; ++f) mean_area += std::abs(uv_signed_area(uv, mesh.faces.row(f)));
  mean_area /= std::max(1, face_count);

  std::vector<int> sound, degenerate;
  for (int f = 0; f < face_count; ++f) {
    const bool usable = tensors.row(f).allFinite() &&
                        std::abs(uv_signed_area(uv, mesh.faces.row(f))) > 1e-12 * mean_area;
    (usable ? sound : degenerate).push_back(f);
  }
  if (degenerate.empty()) {
    return weights == QuasiHarmonicWeights::tensor_cotangent
               ? tensor_cotangent_laplacian(uv, mesh.faces, tensors)
               : tensor_mean_value_laplacian(uv, mesh.faces, tensors);
  }
  Eigen::MatrixX3i sound_faces(static_cast<Eigen::Index>(sound.size()), 3);
  TriangleTensors sound_tensors(static_cast<Eigen::Index>(sound.size()), 4);
  for (std::size_t k = 0; k < sound.size(); ++k) {
    sound_faces.row(static_cast<Eigen::Index>(k)) = mesh.faces.row(sound[k]);
    sound_tensors.row(static_cast<Eigen::Index>(k)) = tensors.row(sound[k]);
  }
  Eigen::SparseMatrix<double> result(mesh.vertex_count(), mesh.vertex_count());
  if (!sound.empty()) {
    result = weights == QuasiHarmonicWeights::tensor_cotangent
                 ? tensor_cotangent_laplacian(uv, sound_faces, sound_tensors)
                 : tensor_mean_value_laplacian(uv, sound_faces, sound_tensors);
  }
  std::vector<Eigen::Triplet<double>> isometric;
  for (const int f : degenerate) {
    const Eigen::Vector3d half_cotangents = cotangent_half_weights(
        mesh.vertices.row(mesh.faces(f, 0)), mesh.vertices.row(mesh.faces(f, 1)),
        mesh.vertices.row(mesh.faces(f, 2)));
    for (int k = 0; k < 3; ++k) {
      const int i = mesh.faces(f, (k + 1) % 3), j = mesh.faces(f, (k + 2) % 3);
      const double w = half_cotangents[k];
      isometric.emplace_back(i, j, -w);
      isometric.emplace_back(j, i, -w);
      isometric.emplace_back(i, i, w);
      isometric.emplace_back(j, j, w);
    }
  }
  Eigen::SparseMatrix<double> isometric_part(mesh.vertex_count(), mesh.vertex_count());
  isometric_part.setFromTriplets(isometric.begin(), isometric.end());
  return result + isometric_part;
}

// C = K^-1 = sqrt(I)^-1 (5.5, 5.7) of `face` under the map `uv`, as quasi_harmonic_tensors
// computes it; false when the uv triangle is degenerate (no Jacobian) or the tensor not finite.
bool face_tensor(const Mesh& mesh, const Eigen::MatrixX2d& uv, const Eigen::Vector3i& face,
                 Eigen::Matrix2d& tensor) {
  Eigen::Matrix<double, 3, 2> edges3d;
  edges3d.col(0) = (mesh.vertices.row(face[1]) - mesh.vertices.row(face[0])).transpose();
  edges3d.col(1) = (mesh.vertices.row(face[2]) - mesh.vertices.row(face[0])).transpose();
  Eigen::Matrix2d edges_uv;
  edges_uv.col(0) = (uv.row(face[1]) - uv.row(face[0])).transpose();
  edges_uv.col(1) = (uv.row(face[2]) - uv.row(face[0])).transpose();
  if (edges_uv.determinant() == 0.0) return false;
  const Eigen::Matrix<double, 3, 2> jacobian = edges3d * edges_uv.inverse();  // dX = J dU (5.1)
  tensor = spd_sqrt(jacobian.transpose() * jacobian).inverse();  // I = J^T J (5.2)
  return tensor.allFinite();
}

// Adds the off-diagonal entries of faces [begin, end) of the tensor-cotangent operator (5.10)
// with the regularization above into `values` (laid out like `pattern`'s stored entries).
void add_tensor_cotangent_faces(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                                const Eigen::SparseMatrix<double>& pattern, double area_floor,
                                int begin, int end, double* values) {
  const int* outer = pattern.outerIndexPtr();
  const int* inner = pattern.innerIndexPtr();
  const auto add = [&](int row, int column, double value) {
    values[std::lower_bound(inner + outer[column], inner + outer[column + 1], row) - inner] +=
        value;
  };
  for (int f = begin; f < end; ++f) {
    const Eigen::Vector3i corner = mesh.faces.row(f);
    Eigen::Matrix2d raw;
    if (face_tensor(mesh, uv, corner, raw) &&
        std::abs(uv_signed_area(uv, corner)) > area_floor) {
      // The edge weights of (5.10) per triangle, as tensor_cotangent_laplacian computes them.
      Eigen::Vector2d rotated_edge[3];
      for (int k = 0; k < 3; ++k) {
        const Eigen::Vector2d edge = uv.row(corner[(k + 2) % 3]) - uv.row(corner[(k + 1) % 3]);
        rotated_edge[k] = Eigen::Vector2d(-edge.y(), edge.x());
      }
      const double twice_area = std::abs(rotated_edge[2].x() * rotated_edge[1].y() -
                                         rotated_edge[2].y() * rotated_edge[1].x());
      if (twice_area == 0.0) continue;
      const Eigen::Matrix2d tensor = 0.5 * (raw + raw.transpose());
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3;
        const double stiffness = rotated_edge[a].dot(tensor * rotated_edge[b]) / (2.0 * twice_area);
        add(corner[a], corner[b], stiffness);
        add(corner[b], corner[a], stiffness);
      }
    } else {
      // No usable Jacobian: the isometric layout's plain cotangent weights.
      const Eigen::Vector3d half_cotangents =
          cotangent_half_weights(mesh.vertices.row(corner[0]), mesh.vertices.row(corner[1]),
                                 mesh.vertices.row(corner[2]));
      for (int k = 0; k < 3; ++k) {
        const int i = corner[(k + 1) % 3], j = corner[(k + 2) % 3];
        add(i, j, -half_cotangents[k]);
        add(j, i, -half_cotangents[k]);
      }
    }
  }
}

// The same operator as quasi_harmonic_operator(mesh, uv, tensor_cotangent), its values written into
// `matrix`, which holds the mesh's adjacency pattern (kept). The faces are split in two fixed
// halves assembled on two threads and then summed: deterministic, whatever the timing.
void assemble_tensor_cotangent(const Mesh& mesh, const Eigen::MatrixX2d& uv,
                               Eigen::SparseMatrix<double>& matrix) {
  const int face_count = mesh.face_count();
  double mean_area = 0.0;
  for (int f = 0; f < face_count; ++f) mean_area += std::abs(uv_signed_area(uv, mesh.faces.row(f)));
  mean_area /= std::max(1, face_count);
  const double area_floor = 1e-12 * mean_area;

  const Eigen::Index nonzeros = matrix.nonZeros();
  double* values = matrix.valuePtr();
  std::fill(values, values + nonzeros, 0.0);
  std::vector<double> second_half(static_cast<std::size_t>(nonzeros), 0.0);
  const int middle = face_count / 2;
  std::future<void> second = detail::start_beside([&] {
    add_tensor_cotangent_faces(mesh, uv, matrix, area_floor, middle, face_count,
                               second_half.data());
  });
  add_tensor_cotangent_faces(mesh, uv, matrix, area_floor, 0, middle, values);
  second.get();
  for (Eigen::Index slot = 0; slot < nonzeros; ++slot) values[slot] += second_half[slot];

  // Diagonal: minus the off-diagonal row sums (the PSD convention of every operator here).
  const int vertex_count = static_cast<int>(matrix.cols());
  const int* outer = matrix.outerIndexPtr();
  const int* inner = matrix.innerIndexPtr();
  std::vector<double> row_sums(static_cast<std::size_t>(vertex_count), 0.0);
  for (int column = 0; column < vertex_count; ++column)
    for (int slot = outer[column]; slot < outer[column + 1]; ++slot)
      if (inner[slot] != column) row_sums[static_cast<std::size_t>(inner[slot])] += values[slot];
  for (int column = 0; column < vertex_count; ++column) {
    const int* diagonal =
        std::lower_bound(inner + outer[column], inner + outer[column + 1], column);
    values[diagonal - inner] = -row_sums[static_cast<std::size_t>(column)];
  }
}

// Start map "plane_projection": every vertex projected onto the least-squares plane (principal
// axes, oriented like the surface), then moved by the similarity that best fits the projected
// fixed vertices to their placed positions; the fixed vertices then take their placed positions.
Eigen::MatrixX2d plane_projection(const Mesh& mesh, const BoundaryPlacement& placement) {
  const Eigen::RowVector3d centroid = mesh.vertices.colwise().mean();
  const Eigen::MatrixX3d centred = mesh.vertices.rowwise() - centroid;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(centred.transpose() * centred);
  const Eigen::Vector3d u_axis = eigen.eigenvectors().col(2);
  Eigen::Vector3d v_axis = eigen.eigenvectors().col(1);
  Eigen::Vector3d area_vector = Eigen::Vector3d::Zero();
  for (int f = 0; f < mesh.face_count(); ++f) {
    const Eigen::Vector3d a = mesh.vertices.row(mesh.faces(f, 0));
    area_vector += (Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, 1))) - a)
                       .cross(Eigen::Vector3d(mesh.vertices.row(mesh.faces(f, 2))) - a);
  }
  if (u_axis.cross(v_axis).dot(area_vector) < 0.0)
    v_axis = -v_axis;  // Keep faces counter-clockwise.
  Eigen::MatrixX2d uv(mesh.vertex_count(), 2);
  uv.col(0) = centred * u_axis;
  uv.col(1) = centred * v_axis;

  // Least-squares similarity z -> s z + t (s complex: rotation and scale, no mirror).
  using Complex = std::complex<double>;
  const Eigen::Index count = placement.vertices.size();
  Complex source_mean = 0.0, target_mean = 0.0;
  for (Eigen::Index k = 0; k < count; ++k) {
    source_mean += Complex(uv(placement.vertices[k], 0), uv(placement.vertices[k], 1));
    target_mean += Complex(placement.uv(k, 0), placement.uv(k, 1));
  }
  source_mean /= static_cast<double>(count);
  target_mean /= static_cast<double>(count);
  Complex numerator = 0.0;
  double denominator = 0.0;
  for (Eigen::Index k = 0; k < count; ++k) {
    const Complex z =
        Complex(uv(placement.vertices[k], 0), uv(placement.vertices[k], 1)) - source_mean;
    const Complex w = Complex(placement.uv(k, 0), placement.uv(k, 1)) - target_mean;
    numerator += std::conj(z) * w;
    denominator += std::norm(z);
  }
  const Complex scale = denominator > 0.0 ? numerator / denominator : Complex(1.0, 0.0);
  for (Eigen::Index v = 0; v < uv.rows(); ++v) {
    const Complex moved = scale * (Complex(uv(v, 0), uv(v, 1)) - source_mean) + target_mean;
    uv.row(v) << moved.real(), moved.imag();
  }
  for (Eigen::Index k = 0; k < count; ++k) uv.row(placement.vertices[k]) = placement.uv.row(k);
  return uv;
}

double bounding_diagonal(const Eigen::MatrixX2d& uv) {
  return (uv.colwise().maxCoeff() - uv.colwise().minCoeff()).norm();
}

// A round may reuse the last Cholesky factor (as a conjugate-gradient preconditioner) while the
// map it was computed from has moved by at most this fraction of the layout's diameter; beyond it,
// convergence is too slow to beat a new factorization. Measured on the face scan (16x): a drift
// of 0.022-0.032 converges in 6 iterations, one of 0.06 needs 11.
constexpr double kStaleFactorDrift = 0.04;
// Iterations a stale-factor solve may take before a factorization is cheaper (one iteration costs
// about a tenth of a factorization).
constexpr int kStaleFactorIterations = 10;

double largest_move(const Eigen::MatrixX2d& from, const Eigen::MatrixX2d& to) {
  const double diameter = bounding_diagonal(to);
  return (to - from).rowwise().norm().maxCoeff() / (diameter > 0.0 ? diameter : 1.0);
}

}  // namespace

struct QuasiHarmonicMapper::Impl {
  Mesh mesh;           // The input scaled to unit size (mesh/power_of_two_scale.h) ...
  double scale = 1.0;  // ... by this power of two.
  QuasiHarmonicOptions options;
  SolveReport setup;
  std::vector<int> loop;
  BoundaryPlacement placement;  // Fixed vertices and positions of every round.
  std::unique_ptr<detail::Backend> backend;
  // The mesh's operator pattern; for a conformal start also the cotangent Laplacian's values
  // (assembled during validation), until a round overwrites them.
  Eigen::SparseMatrix<double> operator_matrix;
  bool holds_cotangent_laplacian = false;
  std::vector<int> vertex_ordering;  // Fill-reducing ordering of the vertices (may be empty).
  std::unique_ptr<detail::DirichletSystem> rounds_system;     // Pattern analyzed once.
  std::unique_ptr<detail::DirichletSystem> conformal_system;  // Only when it cannot share.
  std::unique_ptr<detail::DirichletSystem> positive_system;   // The mean-value fall-back round.

  Impl(const Mesh& input, const QuasiHarmonicOptions& qhm_options)
      : Impl(detail::unit_scaled(input), qhm_options) {}

  Impl(detail::ScaledMesh unit, const QuasiHarmonicOptions& qhm_options)
      : mesh(std::move(unit.mesh)), scale(unit.scale), options(qhm_options) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    if (!detail::validate_mesh_arrays(mesh, setup)) return;
    // The operator pattern and its fill-reducing ordering depend only on the faces: a second
    // thread computes them while this one checks the topology and assembles the start operator
    // (independent work, so the result does not depend on the timing).
    std::future<detail::OperatorPattern> pattern =
        detail::start_beside([this] { return detail::operator_pattern(mesh); });
    loop = detail::validate_disk_topology(mesh, setup);
    if (!setup.ok() || !validate_options()) return;
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    if (!clock.start("assembly")) return;
    const bool conformal_start = options.initial == InitialMap::conformal;
    if (conformal_start) operator_matrix = laplacian(mesh, WeightScheme::cotangent);
    holds_cotangent_laplacian = conformal_start;
    if (!clock.start("analysis")) return;
    detail::OperatorPattern mesh_pattern = pattern.get();
    if (!conformal_start) operator_matrix = std::move(mesh_pattern.pattern);
    vertex_ordering = std::move(mesh_pattern.vertex_ordering);
    place_fixed_vertices();
    const detail::MatrixKind kind = options.weights == QuasiHarmonicWeights::tensor_cotangent
                                        ? detail::MatrixKind::symmetric_positive_definite
                                        : detail::MatrixKind::general;
    rounds_system = std::make_unique<detail::DirichletSystem>(
        operator_matrix, placement.vertices, *backend, kind, options.solver, vertex_ordering);
  }
  bool validate_options() {
    const auto fail = [this](std::string message) {
      setup.status = Status::invalid_input;
      setup.message = std::move(message);
      return false;
    };
    if (options.max_rounds < 1) return fail("quasi-harmonic map: max_rounds must be at least 1");
    if (!(options.stability_tolerance >= 0.0))
      return fail("quasi-harmonic map: stability_tolerance must be >= 0");
    if (options.initial == InitialMap::given) {
      if (options.initial_uv.rows() != mesh.vertex_count())
        return fail("quasi-harmonic map: initial_uv has " +
                    std::to_string(options.initial_uv.rows()) + " rows; the mesh has " +
                    std::to_string(mesh.vertex_count()) + " vertices");
      for (int v = 0; v < mesh.vertex_count(); ++v) {
        if (!options.initial_uv.row(v).allFinite())
          return fail("quasi-harmonic map: initial_uv of vertex " + std::to_string(v) +
                      " is not finite");
      }
      return true;
    }
    return detail::validate_boundary_options(mesh, options.boundary, setup);
  }

  // A given start keeps its own boundary; otherwise the boundary options place it.
  void place_fixed_vertices() {
    if (options.initial == InitialMap::given) {
      placement.vertices =
          Eigen::Map<const Eigen::VectorXi>(loop.data(), static_cast<Eigen::Index>(loop.size()));
      placement.uv.resize(placement.vertices.size(), 2);
      for (Eigen::Index k = 0; k < placement.vertices.size(); ++k)
        placement.uv.row(k) = options.initial_uv.row(placement.vertices[k]);
    } else {
      placement = place_boundary(mesh, loop, options.boundary);
    }
  }

  // Step 1: the start map.
  bool initial_map(Eigen::MatrixX2d& uv, SolveReport& report, detail::PhaseClock& clock) {
    if (!clock.start("initial map")) return false;
    switch (options.initial) {
      case InitialMap::given:
        uv = options.initial_uv;
        return true;
      case InitialMap::plane_projection:
        uv = plane_projection(mesh, placement);
        return true;
      case InitialMap::conformal: {
        detail::DirichletSystem* system = rounds_system.get();
        if (options.weights != QuasiHarmonicWeights::tensor_cotangent) {
          if (!conformal_system)
            conformal_system = std::make_unique<detail::DirichletSystem>(
                operator_matrix, placement.vertices, *backend,
                detail::MatrixKind::symmetric_positive_definite, options.solver, vertex_ordering);
          system = conformal_system.get();
        }
        if (!holds_cotangent_laplacian) {
          operator_matrix = laplacian(mesh, WeightScheme::cotangent);
          holds_cotangent_laplacian = true;
        }
        return system->factorize(operator_matrix, report) &&
               system->solve(placement.uv, uv, report);
      }
    }
    return false;
  }

  // Steps 2-4 for one round: the operator of the current map `uv` and the Dirichlet solve with the
  // same boundary. `factored_map` is the map whose operator was factorized last (empty when the
  // factor is not a round's); a round close to it reuses that factor (see kStaleFactorDrift) and
  // is solved to the accuracy SolverOptions asks of iterative solves: relative residual <=
  // tolerance, and an estimated relative error <= max(tolerance, 1e-8).
  bool one_round(const Eigen::MatrixX2d& uv, Eigen::MatrixX2d& factored_map,
                 Eigen::MatrixX2d& next, SolveReport& report) {
    if (options.weights == QuasiHarmonicWeights::tensor_cotangent) {
      assemble_tensor_cotangent(mesh, uv, operator_matrix);
    } else {
      operator_matrix = quasi_harmonic_operator(mesh, uv, options.weights);
    }
    holds_cotangent_laplacian = false;
    if (!rounds_system->load(operator_matrix, report)) return false;
    if (factored_map.rows() == uv.rows() && rounds_system->has_reusable_factor() &&
        largest_move(factored_map, uv) <= kStaleFactorDrift) {
      const double tolerance = options.solver.tolerance;
      switch (rounds_system->solve_with_stale_factor(placement.uv, std::max(tolerance, 1e-8),
                                                     tolerance, kStaleFactorIterations, next,
                                                     report)) {
        case detail::StaleFactorOutcome::converged:
          return true;
        case detail::StaleFactorOutcome::failed:
          return false;
        case detail::StaleFactorOutcome::too_slow:
          break;
      }
    }
    if (!rounds_system->factorize_loaded(report)) return false;
    factored_map = uv;
    return rounds_system->solve(placement.uv, next, report);
  }

  // The tensor-cotangent weights (5.10) can be negative on badly shaped triangles, and a map from
  // them may fold (cow-cut: one triangle). The tensor mean-value weights (5.4) are positive for
  // any triangle and tensor, so with the convex boundary of a circle or square one more round with
  // them gives a map without a fold (Tutte's theorem): taken when the final map has a flipped or
  // zero-area triangle, and reported in `fallbacks`.
  bool positive_weights_round_if_folded(Eigen::MatrixX2d& uv, SolveReport& report,
                                        detail::PhaseClock& clock) {
    if (options.weights != QuasiHarmonicWeights::tensor_cotangent || !uv.allFinite()) return true;
    const FlipCount flips = count_flips(uv, mesh.faces);
    if (flips.flipped + flips.zero_area == 0) return true;
    if (!clock.start("mean-value round")) return false;
    if (!positive_system)
      positive_system = std::make_unique<detail::DirichletSystem>(
          operator_matrix, placement.vertices, *backend, detail::MatrixKind::general,
          options.solver, vertex_ordering);
    const Eigen::SparseMatrix<double> positive =
        quasi_harmonic_operator(mesh, uv, QuasiHarmonicWeights::tensor_mean_value);
    Eigen::MatrixX2d next;
    if (!positive_system->factorize(positive, report) ||
        !positive_system->solve(placement.uv, next, report))
      return false;
    report.fallbacks.push_back("a last round with tensor mean-value weights (the tensor-cotangent "
                               "map has " + std::to_string(flips.flipped) + " flipped and " +
                               std::to_string(flips.zero_area) + " zero-area triangles)");
    ++report.rounds;
    uv = std::move(next);
    return true;
  }

  QuasiHarmonicResult solve() {
    QuasiHarmonicResult result;
    result.report = setup;
    SolveReport& report = result.report;
    if (!report.ok()) return result;
    detail::PhaseClock clock(report, options.solver.progress);
    Eigen::MatrixX2d uv;
    if (!initial_map(uv, report, clock)) return result;
    if (!uv.allFinite()) {
      report.status = Status::numerical_failure;
      report.message = "quasi-harmonic map: the start map is not finite";
      return result;
    }
    Eigen::MatrixX2d factored_map;  // The start map's factor is not a round's operator.
    for (int round = 1; round <= options.max_rounds; ++round) {
      if (!clock.start("round " + std::to_string(round) + "/" + std::to_string(options.max_rounds),
                       round - 1, options.max_rounds))
        return result;
      Eigen::MatrixX2d next;
      if (!one_round(uv, factored_map, next, report)) return result;
      if (!next.allFinite()) {
        uv = next;  // finish_map reports the failure.
        break;
      }
      const double change = largest_move(uv, next);
      uv = next;
      result.round_change.push_back(change);
      report.rounds = round;
      // Step 5: repeat until the map is stable.
      if (change < options.stability_tolerance) break;
    }
    if (!positive_weights_round_if_folded(uv, report, clock)) return result;
    clock.stop();
    report.cross_check_error = backend->cross_check_error();
    detail::finish_map(mesh, loop, options.normalization, uv, report, clock);
    // Raw layouts lie on the fixed boundary (a circle or square of radius 1, or given positions).
    detail::to_model_units(uv, scale, options.normalization, false);
    result.uv = std::move(uv);
    return result;
  }
};

QuasiHarmonicMapper::QuasiHarmonicMapper(const Mesh& mesh, const QuasiHarmonicOptions& options)
    : impl_(std::make_unique<Impl>(mesh, options)) {}
QuasiHarmonicMapper::~QuasiHarmonicMapper() = default;
QuasiHarmonicMapper::QuasiHarmonicMapper(QuasiHarmonicMapper&&) noexcept = default;
QuasiHarmonicMapper& QuasiHarmonicMapper::operator=(QuasiHarmonicMapper&&) noexcept = default;

const SolveReport& QuasiHarmonicMapper::setup_report() const { return impl_->setup; }

void QuasiHarmonicMapper::update_geometry(const Eigen::MatrixX3d& vertices) {
  Impl& impl = *impl_;
  if (!impl.rounds_system) return;
  if (!detail::accept_new_geometry(impl.mesh, vertices, impl.setup)) return;
  impl.mesh.vertices = vertices * impl.scale;
  impl.holds_cotangent_laplacian = false;  // The start operator belongs to the old geometry.
  impl.place_fixed_vertices();  // Arc-length placements follow the new boundary lengths.
}

QuasiHarmonicResult QuasiHarmonicMapper::solve() { return impl_->solve(); }

QuasiHarmonicResult quasi_harmonic_map(const Mesh& mesh, const QuasiHarmonicOptions& options) {
  QuasiHarmonicMapper mapper(mesh, options);
  return mapper.solve();
}

}  // namespace harmonia
