// Spherical maps (harmonia/spherical_map.h) for Python: the compiled half of harmonia.sphere()
// (python/harmonia/maps.py).

#include <array>
#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "core/numpy_arrays.h"
#include "core/released_call.h"
#include "core/solver_choice.h"
#include "harmonia/laplacian.h"
#include "harmonia/spherical_map.h"

namespace harmonia::python {

namespace {

// The map's phases have no usual shares worth naming: the fraction follows the quasi-harmonic
// rounds the library reports, and ends at 1.
const PhaseShares kSpherePhases = {};

py::dict sphere(const py::handle& positions, const py::handle& faces, const std::string& method,
                std::optional<std::array<long long, 2>> poles, const std::string& weights, int rounds,
                const std::string& backend, const py::object& device, const py::object& progress,
                const py::object& cancel) {
  const Mesh mesh = mesh_from_arrays(positions, faces);
  SphericalMapOptions options;
  if (method == "curvilinear") {
    options.method = SphericalMethod::curvilinear;
  } else if (method == "relaxation") {
    options.method = SphericalMethod::relaxation;
  } else {
    raise_invalid_input("method is \"" + method + "\": expected \"curvilinear\" or \"relaxation\"");
  }
  if (poles)
    options.poles = std::array<int, 2>{vertex_argument("poles[0]", (*poles)[0], mesh),
                                       vertex_argument("poles[1]", (*poles)[1], mesh)};
  const std::optional<WeightScheme> scheme = weight_scheme_from_string(weights);
  if (!scheme || (*scheme != WeightScheme::cotangent && *scheme != WeightScheme::mean_value))
    raise_invalid_input("weights is \"" + weights + "\": expected \"cotangent\" or \"mean-value\"");
  options.weights = *scheme;
  if (rounds < 0) raise_invalid_input("rounds is " + std::to_string(rounds) + ": expected 0 or more");
  options.rounds = rounds;
  options.solver = solver_options(backend, device);
  SphericalMapResult result;
  run_released(python_control(progress, cancel), kSpherePhases, [&](const ProgressCallback& callback) {
    SphericalMapOptions call = options;
    call.solver.progress = callback;
    result = spherical_map(mesh, call);
    return result.report.ok() || result.report.status == Status::flipped_triangles;
  });
  // A map with triangles turned over is still a map (the report counts them); anything else is
  // an error.
  if (result.report.status != Status::flipped_triangles)
    raise_unless_ok(result.report, asks_for_device(options.solver));
  py::list round_distortion;
  for (const SphericalRound& round : result.rounds) round_distortion.append(round.area_distortion);
  py::dict dict;
  dict["positions"] = to_numpy<double>(result.positions);
  dict["angles"] = to_numpy<double>(result.angles);
  dict["north_pole"] = result.north_pole;
  dict["south_pole"] = result.south_pole;
  dict["date_line"] = vector_to_numpy<std::int32_t>(result.date_line);
  dict["round_area_distortion"] = round_distortion;
  dict["relaxed_vertices"] = result.relaxed_vertices;
  dict["report"] = report_dict(result.report);
  return dict;
}

}  // namespace

void bind_sphere(py::module_& module) {
  module.def("sphere", &sphere, py::arg("positions"), py::arg("faces"), py::kw_only(), py::arg("method"),
             py::arg("poles"), py::arg("weights"), py::arg("rounds"), py::arg("backend"), py::arg("device"),
             py::arg("progress"), py::arg("cancel"));
}

}  // namespace harmonia::python
