#pragma once
// The `backend` keyword every call takes: "auto", "cpu" or "vulkan" (as the CLI's --backend).

#include <string>

#include <pybind11/pybind11.h>

#include "harmonia/solver_options.h"

namespace harmonia::python {

//! The solver options of `backend` ("auto", "cpu", "vulkan"; InvalidInputError otherwise) and
//! `device` (None, or a harmonia.VulkanContext to compute on).
[[nodiscard]] SolverOptions solver_options(const std::string& backend, const pybind11::object& device);

//! Whether the caller named the device (a missing one is then an error, not a fall-back).
[[nodiscard]] bool asks_for_device(const SolverOptions& solver);

//! A report's fields as a dict: status, message, backend, solver, device, backend_notice,
//! precision, iterations, rounds, residual, flipped_triangles, fallbacks and timings (a dict
//! phase -> seconds, in the order the phases ran) with seconds (their sum).
[[nodiscard]] pybind11::dict report_dict(const SolveReport& report);

}  // namespace harmonia::python
