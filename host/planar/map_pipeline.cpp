#include "planar/map_pipeline.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

#include "fallback/direct_solvers.h"
#include "harmonia/metrics.h"
#include "harmonia/normalize.h"
#include "harmonia/topology.h"
#include "mesh/adjacency_pattern.h"
#include "planar/boundary_crossings.h"
#include "solve/backend_selection.h"

namespace harmonia::detail {

std::vector<int> validate_disk_input(const Mesh& mesh, SolveReport& report) {
  // Indices and coordinates first: the topology analysis assumes valid indices.
  if (!validate_mesh_arrays(mesh, report)) return {};
  return validate_disk_topology(mesh, report);
}

bool validate_mesh_arrays(const Mesh& mesh, SolveReport& report) {
  std::string message;
  const Status status = check_indices_and_coordinates(mesh, &message);
  if (status == Status::ok) return true;
  report.status = status;
  report.message = std::move(message);
  return false;
}

std::vector<int> validate_disk_topology(const Mesh& mesh, SolveReport& report) {
  std::string message;
  const Status status = check_disk(mesh, &message);
  if (status != Status::ok) {
    report.status = status;
    report.message = std::move(message);
    return {};
  }
  return boundary_loops(mesh).front();
}

OperatorPattern operator_pattern(const Mesh& mesh, bool nested_dissection) {
  OperatorPattern result;
  result.pattern = AdjacencyPattern(mesh.faces, mesh.vertex_count()).take_matrix();
  result.vertex_ordering = nested_dissection ? nested_dissection_ordering(result.pattern)
                                             : fill_reducing_ordering(result.pattern);
  return result;
}

bool validate_boundary_options(const Mesh& mesh, const BoundaryOptions& options,
                               SolveReport& report) {
  if (options.shape != BoundaryShape::given) return true;
  const auto fail = [&report](std::string message) {
    report.status = Status::invalid_input;
    report.message = "given boundary: " + std::move(message);
    return false;
  };
  const Eigen::Index count = options.given_vertices.size();
  if (options.given_uv.rows() != count)
    return fail(std::to_string(count) + " vertices but " + std::to_string(options.given_uv.rows()) +
                " uv rows");
  std::set<int> distinct;
  for (Eigen::Index k = 0; k < count; ++k) {
    const int v = options.given_vertices[k];
    if (v < 0 || v >= mesh.vertex_count())
      return fail("vertex index " + std::to_string(v) + " (entry " + std::to_string(k) +
                  ") is out of range [0, " + std::to_string(mesh.vertex_count()) + ")");
    if (!distinct.insert(v).second) return fail("vertex " + std::to_string(v) + " is given twice");
    if (!options.given_uv.row(k).allFinite())
      return fail("the position of vertex " + std::to_string(v) + " is not finite");
  }
  if (distinct.size() < 2) return fail("at least 2 distinct fixed vertices are needed");
  return true;
}

std::unique_ptr<Backend> choose_backend(const SolverOptions& options, SolveReport& report) {
  std::string message;
  std::unique_ptr<Backend> backend = make_backend(options, &message);
  if (!backend) {
    report.status = Status::unsupported;
    report.message = message;
    return nullptr;
  }
  report.backend = backend->kind();
  report.device = backend->description();
  report.backend_notice = message;  // e.g. why `automatic` ran on the CPU
  // Devices compute in float; the solver layer refines the solution in double on the host.
  if (backend->kind() == BackendKind::vulkan) report.precision = "float (refined in double)";
  return backend;
}

bool PhaseClock::start(std::string_view phase, int step, int total) {
  stop();
  if (progress_ && !progress_(Progress{phase, step, total})) {
    report_.status = Status::cancelled;
    report_.message = "cancelled by the progress callback at \"" + std::string(phase) + "\"";
    return false;
  }
  phase_ = phase;
  started_ = std::chrono::steady_clock::now();
  running_ = true;
  return true;
}

void PhaseClock::stop() {
  if (!running_) return;
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - started_;
  report_.timings.push_back(PhaseTiming{phase_, elapsed.count()});
  running_ = false;
}

void to_model_units(Eigen::MatrixX2d& uv, double scale, UvNormalization normalization,
                    bool raw_in_model_units) {
  const bool model_sized = normalization == UvNormalization::match_surface_area ||
                           (normalization == UvNormalization::none && raw_in_model_units);
  if (model_sized && scale != 1.0) uv /= scale;
}

void finish_map(const Mesh& mesh, const std::vector<int>& loop, UvNormalization normalization,
                Eigen::MatrixX2d& uv, SolveReport& report, PhaseClock& clock) {
  if (!uv.allFinite()) {
    report.status = Status::numerical_failure;
    report.message = "the computed map has non-finite coordinates (degenerate input triangles?)";
    uv.resize(0, 2);
    return;
  }
  if (!clock.start("normalize")) {
    uv.resize(0, 2);
    return;
  }
  normalize_uv(mesh, mesh.faces, uv, normalization);
  if (!clock.start("validity")) {
    uv.resize(0, 2);
    return;
  }
  const FlipCount flips = count_flips(uv, mesh.faces);
  report.flipped_triangles = flips.flipped;
  report.degenerate_triangles = flips.zero_area;
  report.boundary_self_intersections = count_loop_self_intersections(uv, loop);
  clock.stop();
  if (report.status == Status::ok && flips.flipped + flips.zero_area > 0) {
    report.status = Status::flipped_triangles;
    report.message = std::to_string(flips.flipped) + " flipped and " +
                     std::to_string(flips.zero_area) + " zero-area triangles in the map";
  } else if (report.status == Status::ok && flips.tiny > 0) {
    // A valid map, but part of it is too small to carry any texture: say so.
    report.message = "valid map, but " + std::to_string(flips.tiny) +
                     " triangles have less than 1e-14 of the total UV area (a protrusion that "
                     "the cut leaves closed shrinks exponentially; cutting through it helps)";
  }
}

bool accept_new_geometry(const Mesh& mesh, const Eigen::MatrixX3d& vertices, SolveReport& setup) {
  setup.status = Status::ok;
  setup.message.clear();
  setup.timings.clear();
  if (vertices.rows() == mesh.vertex_count() && vertices.allFinite()) return true;
  setup.status = Status::invalid_input;
  setup.message = "update_geometry: expected " + std::to_string(mesh.vertex_count()) +
                  " finite vertex rows, got " + std::to_string(vertices.rows()) +
                  (vertices.allFinite() ? "" : " (some not finite)");
  return false;
}

}  // namespace harmonia::detail
