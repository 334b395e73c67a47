#include "core/bindings.h"
#include "core/vulkan_device.h"

#include <optional>
#include <string>

#include <pybind11/stl.h>

#include "core/errors.h"

#if HARMONIA_HAVE_VULKAN
#include "harmonia/vulkan_context.h"
#endif

namespace harmonia::python {

namespace py = pybind11;

namespace {

// Holds the shared context (empty in builds without Vulkan, whose constructor raises).
struct VulkanContextHolder {
  std::shared_ptr<vulkan::Context> context;
};

}  // namespace

void bind_vulkan_context(py::module_& module) {
  py::class_<VulkanContextHolder>(module, "VulkanContext")
      .def(py::init([](const std::string& device_name, std::optional<int> device_index, bool validation,
                       bool float64) {
             VulkanContextHolder holder;
#if HARMONIA_HAVE_VULKAN
             vulkan::ContextOptions options;
             options.device_name = device_name;
             options.device_index = device_index;
             options.enable_validation = validation;
             options.enable_float64 = float64;
             const py::gil_scoped_release released;  // creating a device takes a while
             holder.context = std::make_shared<vulkan::Context>(vulkan::Context::create(options));
#else
             (void)device_name, (void)device_index, (void)validation, (void)float64;
             raise_status(Status::unsupported, "this harmonia was built without the Vulkan backend");
#endif
             return holder;
           }),
           py::kw_only(), py::arg("device_name") = "", py::arg("device_index") = py::none(),
           py::arg("validation") = false, py::arg("float64") = false)
      .def_property_readonly("name",
                             [](const VulkanContextHolder& holder) -> std::string {
#if HARMONIA_HAVE_VULKAN
                               return holder.context->device().name;
#else
                               (void)holder;
                               return {};
#endif
                             })
      .def_property_readonly("type",
                             [](const VulkanContextHolder& holder) -> std::string {
#if HARMONIA_HAVE_VULKAN
                               return std::string(vulkan::to_string(holder.context->device().type));
#else
                               (void)holder;
                               return {};
#endif
                             })
      .def_property_readonly("float64", [](const VulkanContextHolder& holder) {
#if HARMONIA_HAVE_VULKAN
        return holder.context->device().float64_enabled;
#else
        (void)holder;
        return false;
#endif
      });
}

std::shared_ptr<vulkan::Context> shared_context(const py::object& device) {
  if (!py::isinstance<VulkanContextHolder>(device))
    raise_invalid_input("device is a " + std::string(py::str(py::type::of(device))) +
                        ": expected a harmonia.VulkanContext or None");
  return device.cast<const VulkanContextHolder&>().context;
}

}  // namespace harmonia::python
