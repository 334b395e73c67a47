// Process-wide settings the caller may choose (harmonia/blas_threads.h): the package changes none
// by itself, as the library promises.

#include <string>

#include <pybind11/pybind11.h>

#include "core/bindings.h"
#include "core/errors.h"
#include "harmonia/blas_threads.h"

namespace harmonia::python {

namespace {

std::string policy_name(BlasThreadPolicy policy) {
  switch (policy) {
    case BlasThreadPolicy::leave_alone:
      return "leave_alone";
    case BlasThreadPolicy::hold_during_split_factorizations:
      return "hold_during_split_factorizations";
  }
  return "leave_alone";  // Unreachable: -Werror=switch keeps the list above complete.
}

std::string set_policy(const std::string& name) {
  BlasThreadPolicy policy = BlasThreadPolicy::leave_alone;
  if (name == "hold_during_split_factorizations") {
    policy = BlasThreadPolicy::hold_during_split_factorizations;
  } else if (name != "leave_alone") {
    raise_invalid_input("policy is \"" + name +
                        "\": expected \"leave_alone\" or \"hold_during_split_factorizations\"");
  }
  return policy_name(set_blas_thread_policy(policy));
}

}  // namespace

void bind_process_settings(py::module_& module) {
  module.def("set_blas_thread_policy", &set_policy, py::arg("policy"));
  module.def("blas_thread_policy", [] { return policy_name(blas_thread_policy()); });
}

}  // namespace harmonia::python
