#pragma once
// The bridge from the library's statuses to the exceptions of harmonia.errors (python/harmonia/
// errors.py): a report that is not ok, and a harmonia::Error the library throws, both become the
// class of their status, with the library's one-line message.

#include <string>

#include <pybind11/pybind11.h>

#include "harmonia/types.h"

namespace harmonia::python {

//! Throws the harmonia.errors exception of `status` with `message` (as pybind11::error_already_set,
//! so that it crosses the C++ frames back to Python). `asked_for_device`: the caller named the
//! Vulkan backend, so a missing device (Status::unsupported) is the device error the Python API
//! promises, not a silent fall-back.
[[noreturn]] void raise_status(Status status, const std::string& message, bool asked_for_device = false);

//! Raises `report`'s status unless it is ok.
void raise_unless_ok(const SolveReport& report, bool asked_for_device = false);

//! Raises harmonia.errors.InvalidInputError (a ValueError) with `message`.
[[noreturn]] void raise_invalid_input(const std::string& message);

//! Registers the translation of harmonia::Error (thrown by readers, writers and devices) into the
//! harmonia.errors class of its status, for every function of the module.
void register_error_translation();

}  // namespace harmonia::python
