#pragma once
// The parts of the compiled module harmonia._core, one function per concern (module.cpp calls
// them in order).

#include <pybind11/pybind11.h>

namespace harmonia::python {

namespace py = pybind11;

void bind_mesh_io(py::module_& module);     // mesh_io_binding.cpp
void bind_gltf(py::module_& module);        // gltf_binding.cpp
void bind_atlas(py::module_& module);       // atlas_binding.cpp
void bind_process_settings(py::module_& module);  // process_settings_binding.cpp
void bind_sphere(py::module_& module);      // sphere_binding.cpp
void bind_topology(py::module_& module);    // topology_binding.cpp
void bind_editing(py::module_& module);     // editing_binding.cpp
void bind_planar(py::module_& module);      // planar_binding.cpp
void bind_transfer(py::module_& module);    // transfer_binding.cpp
void bind_reusable_mappers(py::module_& module);  // reusable_mappers_binding.cpp
//! The VulkanContext class (in builds without Vulkan its constructor raises UnsupportedError).
void bind_vulkan_context(py::module_& module);  // vulkan_device.cpp

}  // namespace harmonia::python
