#include "core/errors.h"

namespace harmonia::python {

namespace py = pybind11;

namespace {

// The exception object harmonia.errors makes for a status name and a message.
py::object error_object(Status status, const std::string& message) {
  const py::module_ errors = py::module_::import("harmonia.errors");
  return errors.attr("error_for")(std::string(to_string(status)), message);
}

}  // namespace

void raise_status(Status status, const std::string& message, bool asked_for_device) {
  if (asked_for_device && status == Status::unsupported) status = Status::device_failure;
  const py::object error = error_object(status, message);
  PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(error.ptr())), error.ptr());
  throw py::error_already_set();
}

void raise_unless_ok(const SolveReport& report, bool asked_for_device) {
  if (!report.ok()) raise_status(report.status, report.message, asked_for_device);
}

void raise_invalid_input(const std::string& message) { raise_status(Status::invalid_input, message); }

void register_error_translation() {
  py::register_exception_translator([](std::exception_ptr thrown) {
    if (!thrown) return;
    try {
      std::rethrow_exception(thrown);
    } catch (const harmonia::Error& error) {
      const py::object object = error_object(error.status(), error.what());
      PyErr_SetObject(reinterpret_cast<PyObject*>(Py_TYPE(object.ptr())), object.ptr());
    }
  });
}

}  // namespace harmonia::python
