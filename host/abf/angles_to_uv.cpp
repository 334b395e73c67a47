// From planar corner angles to UVs (thesis section 3.3): validation, the choice of the two pinned
// vertices, one of the two reconstructions (detail/angle_reconstruction_*), then the finishing
// every map shares (normalization, flips, boundary self-intersections).
//
// Pins (default): the two boundary vertices farthest apart in 3D, ties to the lexicographically
// first pair (the rule of LSCM): far apart, the pins condition the least-squares system best.
// The first pin goes to (0, 0), the second to (d, 0) with d their 3D distance, so the raw layout
// (UvNormalization::none) has about the surface's scale. Greedy starts at the first pin's first
// face and its layout is moved by the similarity that puts the pins at the same two places, so
// both methods return their raw layouts in the same frame.

#include "harmonia/angles_to_uv.h"

#include <cmath>
#include <complex>
#include <future>
#include <memory>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "abf/angle_reconstruction_greedy.h"
#include "abf/angle_reconstruction_least_squares.h"
#include "abf/validated_angles_to_uv.h"
#include "mesh/number_text.h"
#include "mesh/power_of_two_scale.h"
#include "planar/boundary_pins.h"
#include "planar/map_pipeline.h"
#include "mesh/helper_tasks.h"

namespace harmonia {
namespace {

// Sets invalid_input naming the first face whose angles are missing, not finite or outside
// (0, pi); returns false then.
bool validate_angles(const Mesh& mesh, const Eigen::MatrixX3d& angles, SolveReport& report) {
  const auto fail = [&report](std::string message) {
    report.status = Status::invalid_input;
    report.message = "angles_to_uv: " + std::move(message);
    return false;
  };
  if (angles.rows() != mesh.face_count())
    return fail("expected one row of 3 angles per face (" + std::to_string(mesh.face_count()) +
                "), got " + std::to_string(angles.rows()) + " rows");
  for (int f = 0; f < mesh.face_count(); ++f) {
    for (int k = 0; k < 3; ++k) {
      const double angle = angles(f, k);
      if (std::isfinite(angle) && angle > 0.0 && angle < std::numbers::pi) continue;
      return fail("the angle of face " + std::to_string(f) + " at corner " + std::to_string(k) +
                  " (vertex " + std::to_string(mesh.faces(f, k)) + ") is " +
                  (std::isfinite(angle) ? detail::number_text(angle) : std::string("not finite")) +
                  "; angles must lie in (0, pi)");
    }
  }
  return true;
}

// The pins of `options`, completed by the default rule; invalid_input when out of range or equal.
bool choose_pins(const Mesh& mesh, const std::vector<int>& loop, const AnglesToUvOptions& options,
                 detail::LayoutPins& pins, SolveReport& report) {
  const auto [far_a, far_b] = detail::farthest_boundary_pair(mesh, loop);
  pins.first = options.pin_first.value_or(far_a);
  pins.second = options.pin_second.value_or(far_b);
  // One pin given: the other is the end of the farthest pair that differs from it.
  if (options.pin_first && !options.pin_second) pins.second = far_a != pins.first ? far_a : far_b;
  if (!options.pin_first && options.pin_second) pins.first = far_a != pins.second ? far_a : far_b;
  for (const int pin : {pins.first, pins.second}) {
    if (pin < 0 || pin >= mesh.vertex_count()) {
      report.status = Status::invalid_input;
      report.message = "angles_to_uv: pinned vertex " + std::to_string(pin) +
                       " is out of range [0, " + std::to_string(mesh.vertex_count()) + ")";
      return false;
    }
  }
  if (pins.first == pins.second) {
    report.status = Status::invalid_input;
    report.message = "angles_to_uv: the two pinned vertices must differ (both are " +
                     std::to_string(pins.first) + ")";
    return false;
  }
  const double distance = (mesh.vertices.row(pins.first) - mesh.vertices.row(pins.second)).norm();
  pins.distance = distance > 0.0 ? distance : 1.0;
  return true;
}

// Moves `uv` by the similarity that takes the pins to (0, 0) and (distance, 0); left as it is when
// the pins coincide in `uv` (a degenerate layout, reported by the flip count).
void move_to_pins(const detail::LayoutPins& pins, Eigen::MatrixX2d& uv) {
  const std::complex<double> origin(uv(pins.first, 0), uv(pins.first, 1));
  const std::complex<double> second(uv(pins.second, 0), uv(pins.second, 1));
  if (second == origin) return;
  const std::complex<double> factor = pins.distance / (second - origin);
  for (Eigen::Index v = 0; v < uv.rows(); ++v) {
    const std::complex<double> moved = factor * (std::complex<double>(uv(v, 0), uv(v, 1)) - origin);
    uv.row(v) << moved.real(), moved.imag();
  }
}

// Pins, reconstruction and finishing, for input that has been validated (by either entry point).
void lay_out(const Mesh& mesh, const Eigen::MatrixX3d& angles, const AnglesToUvOptions& options,
             const detail::ValidatedAngleInput& input, MapResult& result,
             detail::PhaseClock& clock) {
  SolveReport& report = result.report;
  detail::PreparedLayout* prepared = input.prepared;
  detail::LayoutPins pins;
  if (prepared != nullptr)
    pins = prepared->pins;
  else if (!choose_pins(mesh, input.loop, options, pins, report))
    return;

  if (options.method == AngleReconstruction::least_squares) {
    std::unique_ptr<detail::PreparedLayout> own;
    if (prepared == nullptr) {
      own = std::make_unique<detail::PreparedLayout>();
      own->backend = detail::choose_backend(options.solver, report);
      if (!own->backend) return;
      own->pins = pins;
      own->system =
          std::make_unique<detail::LeastSquaresLayout>(mesh, pins, *own->backend, options.solver);
      own->system->set_vertex_ordering(input.vertex_ordering);
      prepared = own.get();
    }
    result.uv = prepared->system->layout(angles, report, clock);
    report.cross_check_error = prepared->backend->cross_check_error();
    if (!report.ok()) {
      result.uv.resize(0, 2);
      return;
    }
  } else {
    // No linear algebra: the layout is computed on the host whatever the backend option says.
    if (!clock.start("layout")) return;
    report.solver = "greedy-breadth-first";
    result.uv = detail::greedy_layout(mesh, angles, pins.first);
    move_to_pins(pins, result.uv);
  }
  detail::finish_map(mesh, input.loop, options.normalization, result.uv, report, clock);
  // Greedy with very inconsistent angles can grow coordinates past what normalization can scale
  // (finite before, overflowing after): say so instead of returning non-finite UVs.
  if (result.uv.rows() > 0 && !result.uv.allFinite()) {
    report.status = Status::numerical_failure;
    report.message =
        "angles_to_uv: the greedy layout diverged (the angles are too inconsistent for a "
        "face-by-face construction); use the least-squares reconstruction";
    result.uv.resize(0, 2);
  }
}

// The reconstruction on a mesh already scaled to unit size (angles_to_uv() below scales it).
MapResult angles_to_uv_at_unit_size(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                    const AnglesToUvOptions& options) {
  MapResult result;
  SolveReport& report = result.report;
  detail::PhaseClock clock(report, options.solver.progress);
  if (!clock.start("validation")) return result;
  if (!detail::validate_mesh_arrays(mesh, report)) return result;
  const bool least_squares = options.method == AngleReconstruction::least_squares;
  // The fill-reducing ordering depends only on the faces: a second thread computes it while this
  // one validates (the tasks are independent, so the result does not depend on their timing).
  std::future<detail::OperatorPattern> ordering;
  if (least_squares)
    ordering = detail::start_beside([&mesh] { return detail::operator_pattern(mesh); });
  const std::vector<int> loop = detail::validate_disk_topology(mesh, report);
  if (!report.ok() || !validate_angles(mesh, angles, report)) return result;
  const std::vector<int> vertex_ordering =
      least_squares ? ordering.get().vertex_ordering : std::vector<int>();
  lay_out(mesh, angles, options, detail::ValidatedAngleInput{loop, vertex_ordering}, result, clock);
  return result;
}

}  // namespace

MapResult angles_to_uv(const Mesh& input, const Eigen::MatrixX3d& angles,
                       const AnglesToUvOptions& options) {
  // Computed on the mesh scaled to unit size (mesh/power_of_two_scale.h); the layout, whose pins
  // sit at their 3D distance, comes back in the model's units.
  const detail::ScaledMesh unit = detail::unit_scaled(input);
  MapResult result = angles_to_uv_at_unit_size(unit.mesh, angles, options);
  detail::to_model_units(result.uv, unit.scale, options.normalization, true);
  return result;
}

namespace detail {

std::unique_ptr<PreparedLayout> prepare_layout(const Mesh& mesh, const AnglesToUvOptions& options,
                                               const std::vector<int>& loop) {
  if (options.method != AngleReconstruction::least_squares) return nullptr;
  SolveReport report;  // Failures here are reported again by the reconstruction itself.
  auto prepared = std::make_unique<PreparedLayout>();
  if (!choose_pins(mesh, loop, options, prepared->pins, report)) return nullptr;
  prepared->backend = choose_backend(options.solver, report);
  if (!prepared->backend) return nullptr;
  prepared->overlappable = prepared->backend->supports(Feature::direct_factorization);
  prepared->system =
      std::make_unique<LeastSquaresLayout>(mesh, prepared->pins, *prepared->backend, options.solver);
  return prepared;
}

MapResult angles_to_uv_validated(const Mesh& mesh, const Eigen::MatrixX3d& angles,
                                 const AnglesToUvOptions& options,
                                 const ValidatedAngleInput& input) {
  MapResult result;
  PhaseClock clock(result.report, options.solver.progress);
  lay_out(mesh, angles, options, input, result, clock);
  return result;
}

}  // namespace detail
}  // namespace harmonia
