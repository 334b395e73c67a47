// harmonia._core: the compiled half of the Python package (python/harmonia/ is the other). It
// converts numpy arrays, releases the interpreter lock around the library's calls and turns the
// library's statuses into harmonia.errors; the documented API is the pure-Python package.

#include <pybind11/pybind11.h>

#include "core/bindings.h"
#include "core/errors.h"

PYBIND11_MODULE(_core, module) {
  module.doc() = "The compiled core of the harmonia package (use the harmonia package itself).";
  harmonia::python::register_error_translation();
  harmonia::python::bind_process_settings(module);
  harmonia::python::bind_vulkan_context(module);
  harmonia::python::bind_mesh_io(module);
  harmonia::python::bind_gltf(module);
  harmonia::python::bind_atlas(module);
  harmonia::python::bind_topology(module);
  harmonia::python::bind_sphere(module);
  harmonia::python::bind_editing(module);
  harmonia::python::bind_planar(module);
  harmonia::python::bind_transfer(module);
  harmonia::python::bind_reusable_mappers(module);
#ifdef HARMONIA_VERSION
  module.attr("__version__") = HARMONIA_VERSION;
#endif
}
