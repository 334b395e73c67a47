#pragma once
// harmonia.VulkanContext: a Vulkan device created once and shared by any number of calls (and
// Python threads), passed as `device=`.

#include <memory>

#include <pybind11/pybind11.h>

#include "harmonia/solver_options.h"

namespace harmonia::python {

//! The context of a harmonia.VulkanContext object (InvalidInputError for anything else).
[[nodiscard]] std::shared_ptr<vulkan::Context> shared_context(const pybind11::object& device);

}  // namespace harmonia::python
