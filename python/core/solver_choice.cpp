#include "core/solver_choice.h"

#include "core/errors.h"
#include "core/vulkan_device.h"

namespace harmonia::python {

namespace py = pybind11;

SolverOptions solver_options(const std::string& backend, const py::object& device) {
  SolverOptions solver;
  if (backend == "auto") {
    solver.backend = BackendChoice::automatic;
  } else if (backend == "cpu") {
    solver.backend = BackendChoice::cpu;
  } else if (backend == "vulkan") {
    solver.backend = BackendChoice::vulkan;
  } else {
    raise_invalid_input("backend is \"" + backend + "\": expected \"auto\", \"cpu\" or \"vulkan\"");
  }
  if (!device.is_none()) solver.vulkan_context = shared_context(device);
  return solver;
}

bool asks_for_device(const SolverOptions& solver) { return solver.backend == BackendChoice::vulkan; }

py::dict report_dict(const SolveReport& report) {
  py::dict timings;
  for (const PhaseTiming& timing : report.timings) {
    // A phase that ran twice (a retried round) adds up.
    const py::str phase(timing.phase);
    timings[phase] = (timings.contains(phase) ? timings[phase].cast<double>() : 0.0) + timing.seconds;
  }
  py::list fallbacks;
  for (const std::string& line : report.fallbacks) fallbacks.append(line);
  py::dict dict;
  dict["status"] = std::string(to_string(report.status));
  dict["message"] = report.message;
  dict["backend"] = std::string(to_string(report.backend));
  dict["solver"] = report.solver;
  dict["device"] = report.device;
  dict["backend_notice"] = report.backend_notice;
  dict["precision"] = report.precision;
  dict["iterations"] = report.iterations;
  dict["rounds"] = report.rounds;
  dict["residual"] = report.residual;
  dict["flipped_triangles"] = report.flipped_triangles;
  dict["fallbacks"] = fallbacks;
  dict["timings"] = timings;
  dict["seconds"] = report.total_seconds();
  return dict;
}

}  // namespace harmonia::python
