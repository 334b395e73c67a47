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
#include <string>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "detail/map_pipeline.h"
#include "harmonia/laplacian.h"
#include "harmonia/quasi_harmonic_operator.h"

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

}  // namespace

struct QuasiHarmonicMapper::Impl {
  Mesh mesh;
  QuasiHarmonicOptions options;
  SolveReport setup;
  std::vector<int> loop;
  BoundaryPlacement placement;  // Fixed vertices and positions of every round.
  std::unique_ptr<detail::Backend> backend;
  std::unique_ptr<detail::DirichletSystem> rounds_system;     // Pattern analyzed once.
  std::unique_ptr<detail::DirichletSystem> conformal_system;  // Only when it cannot share.

  Impl(const Mesh& input, const QuasiHarmonicOptions& qhm_options)
      : mesh(input), options(qhm_options) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    loop = detail::validate_disk_input(mesh, setup);
    if (!setup.ok() || !validate_options()) return;
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    if (!clock.start("analysis")) return;
    place_fixed_vertices();
    const detail::MatrixKind kind = options.weights == QuasiHarmonicWeights::tensor_cotangent
                                        ? detail::MatrixKind::symmetric_positive_definite
                                        : detail::MatrixKind::general;
    rounds_system = std::make_unique<detail::DirichletSystem>(
        mesh.vertex_count(), mesh.faces, placement.vertices, *backend, kind, options.solver);
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
                mesh.vertex_count(), mesh.faces, placement.vertices, *backend,
                detail::MatrixKind::symmetric_positive_definite, options.solver);
          system = conformal_system.get();
        }
        return system->factorize(laplacian(mesh, WeightScheme::cotangent), report) &&
               system->solve(placement.uv, uv, report);
      }
    }
    return false;
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
    for (int round = 1; round <= options.max_rounds; ++round) {
      // Steps 2-4: tensors of the current map, operator, Dirichlet solve with the same boundary.
      if (!clock.start("round " + std::to_string(round) + "/" + std::to_string(options.max_rounds),
                       round - 1, options.max_rounds))
        return result;
      const Eigen::SparseMatrix<double> operator_matrix =
          quasi_harmonic_operator(mesh, uv, options.weights);
      Eigen::MatrixX2d next;
      if (!rounds_system->factorize(operator_matrix, report) ||
          !rounds_system->solve(placement.uv, next, report))
        return result;
      if (!next.allFinite()) {
        uv = next;  // finish_map reports the failure.
        break;
      }
      const double diameter = bounding_diagonal(next);
      const double change =
          (next - uv).rowwise().norm().maxCoeff() / (diameter > 0.0 ? diameter : 1.0);
      uv = next;
      result.round_change.push_back(change);
      report.rounds = round;
      // Step 5: repeat until the map is stable.
      if (change < options.stability_tolerance) break;
    }
    clock.stop();
    detail::finish_map(mesh, options.normalization, uv, report, clock);
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
  impl.setup.status = Status::ok;
  impl.setup.message.clear();
  if (vertices.rows() != impl.mesh.vertex_count() || !vertices.allFinite()) {
    impl.setup.status = Status::invalid_input;
    impl.setup.message = "update_geometry: expected " + std::to_string(impl.mesh.vertex_count()) +
                         " finite vertex rows, got " + std::to_string(vertices.rows());
    return;
  }
  impl.mesh.vertices = vertices;
  impl.place_fixed_vertices();  // Arc-length placements follow the new boundary lengths.
}

QuasiHarmonicResult QuasiHarmonicMapper::solve() { return impl_->solve(); }

QuasiHarmonicResult quasi_harmonic_map(const Mesh& mesh, const QuasiHarmonicOptions& options) {
  QuasiHarmonicMapper mapper(mesh, options);
  return mapper.solve();
}

}  // namespace harmonia
