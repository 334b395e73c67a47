// Fixed-boundary maps (thesis chapter 4, eq. 6.1): the boundary is placed on a convex shape and
// every free vertex is a weighted average of its neighbours, L_II u_I = -L_IB u_B.

#include "harmonia/fixed_boundary_map.h"

#include <future>
#include <utility>

#include "mesh/power_of_two_scale.h"
#include "planar/map_pipeline.h"
#include "mesh/helper_tasks.h"

namespace harmonia {

struct FixedBoundaryMapper::Impl {
  Mesh mesh;            // The input scaled to unit size (mesh/power_of_two_scale.h) ...
  double scale = 1.0;   // ... by this power of two.
  FixedBoundaryOptions options;
  SolveReport setup;  // Status and timings of construction and the latest update_geometry.
  std::vector<int> loop;
  BoundaryPlacement placement;
  std::unique_ptr<detail::Backend> backend;
  std::unique_ptr<detail::DirichletSystem> system;

  Impl(const Mesh& input, const FixedBoundaryOptions& map_options)
      : Impl(detail::unit_scaled(input), map_options) {}

  Impl(detail::ScaledMesh unit, const FixedBoundaryOptions& map_options)
      : mesh(std::move(unit.mesh)), scale(unit.scale), options(map_options) {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("validation")) return;
    if (!detail::validate_mesh_arrays(mesh, setup)) return;
    // The fill-reducing ordering depends only on the faces: a second thread computes it while this
    // one checks the topology and assembles the operator. The tasks are independent, so the result
    // does not depend on their timing.
    std::future<detail::OperatorPattern> ordering =
        detail::start_beside([this] { return detail::operator_pattern(mesh); });
    loop = detail::validate_disk_topology(mesh, setup);
    if (!setup.ok() || !detail::validate_boundary_options(mesh, options.boundary, setup)) return;
    backend = detail::choose_backend(options.solver, setup);
    if (!backend) return;
    if (!clock.start("assembly")) return;
    const Eigen::SparseMatrix<double> operator_matrix = laplacian(mesh, options.weights);
    if (!clock.start("analysis")) return;
    const std::vector<int> vertex_ordering = ordering.get().vertex_ordering;
    placement = place_boundary(mesh, loop, options.boundary);
    // Symmetric schemes give a symmetric L_II, positive definite for sound triangles (Cholesky);
    // ring-based schemes are non-symmetric (LU).
    const detail::MatrixKind kind = is_symmetric(options.weights)
                                        ? detail::MatrixKind::symmetric_positive_definite
                                        : detail::MatrixKind::general;
    system = std::make_unique<detail::DirichletSystem>(
        operator_matrix, placement.vertices, *backend, kind, options.solver, vertex_ordering);
    if (!clock.start("factorization")) return;
    if (!system->factorize(operator_matrix, setup)) return;
  }

  void assemble_and_factorize() {
    detail::PhaseClock clock(setup, options.solver.progress);
    if (!clock.start("assembly")) return;
    const Eigen::SparseMatrix<double> operator_matrix = laplacian(mesh, options.weights);
    if (!clock.start("factorization")) return;
    if (!system->factorize(operator_matrix, setup)) return;
  }

  MapResult solve_with(const Eigen::MatrixX2d& boundary_uv) {
    MapResult result;
    result.report = setup;
    SolveReport& report = result.report;
    if (!report.ok()) return result;
    if (boundary_uv.rows() != placement.vertices.size() || !boundary_uv.allFinite()) {
      report.status = Status::invalid_input;
      report.message = "boundary positions: expected " + std::to_string(placement.vertices.size()) +
                       " finite rows (one per fixed vertex), got " +
                       std::to_string(boundary_uv.rows());
      return result;
    }
    detail::PhaseClock clock(report, options.solver.progress);
    if (!clock.start("solve")) return result;
    if (!system->solve(boundary_uv, result.uv, report)) {
      result.uv.resize(0, 2);
      return result;
    }
    report.cross_check_error = backend->cross_check_error();
    detail::finish_map(mesh, loop, options.normalization, result.uv, report, clock);
    // Raw layouts lie on the caller's boundary (a circle of radius 1, or given positions).
    detail::to_model_units(result.uv, scale, options.normalization, false);
    return result;
  }
};

FixedBoundaryMapper::FixedBoundaryMapper(const Mesh& mesh, const FixedBoundaryOptions& options)
    : impl_(std::make_unique<Impl>(mesh, options)) {}
FixedBoundaryMapper::~FixedBoundaryMapper() = default;
FixedBoundaryMapper::FixedBoundaryMapper(FixedBoundaryMapper&&) noexcept = default;
FixedBoundaryMapper& FixedBoundaryMapper::operator=(FixedBoundaryMapper&&) noexcept = default;

const SolveReport& FixedBoundaryMapper::setup_report() const { return impl_->setup; }

const BoundaryPlacement& FixedBoundaryMapper::placement() const { return impl_->placement; }

void FixedBoundaryMapper::update_geometry(const Eigen::MatrixX3d& vertices) {
  Impl& impl = *impl_;
  // A failed validation cannot be repaired by new positions of the same connectivity.
  if (!impl.system) return;
  if (!detail::accept_new_geometry(impl.mesh, vertices, impl.setup)) return;
  impl.mesh.vertices = vertices * impl.scale;
  // Arc-length placements follow the new boundary lengths; given positions stay as given.
  impl.placement = place_boundary(impl.mesh, impl.loop, impl.options.boundary);
  impl.assemble_and_factorize();
}

MapResult FixedBoundaryMapper::solve() { return impl_->solve_with(impl_->placement.uv); }

MapResult FixedBoundaryMapper::solve(const Eigen::MatrixX2d& boundary_uv) {
  return impl_->solve_with(boundary_uv);
}

MapResult fixed_boundary_map(const Mesh& mesh, const FixedBoundaryOptions& options) {
  FixedBoundaryMapper mapper(mesh, options);
  return mapper.solve();
}

}  // namespace harmonia
