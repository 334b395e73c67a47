#include "harmonia/types.h"

namespace harmonia {

std::string_view to_string(Status status) {
  switch (status) {
    case Status::ok: return "ok";
    case Status::invalid_input: return "invalid_input";
    case Status::parse_error: return "parse_error";
    case Status::io_error: return "io_error";
    case Status::not_a_disk: return "not_a_disk";
    case Status::not_a_sphere: return "not_a_sphere";
    case Status::non_manifold: return "non_manifold";
    case Status::not_converged: return "not_converged";
    case Status::numerical_failure: return "numerical_failure";
    case Status::flipped_triangles: return "flipped_triangles";
    case Status::cancelled: return "cancelled";
    case Status::unsupported: return "unsupported";
    case Status::device_failure: return "device_failure";
  }
  return "unknown";  // Unreachable for valid enum values; -Werror=switch keeps the list complete.
}

std::string_view to_string(BackendKind kind) {
  switch (kind) {
    case BackendKind::cpu: return "cpu";
    case BackendKind::vulkan: return "vulkan";
  }
  return "unknown";
}

double SolveReport::total_seconds() const noexcept {
  double total = 0.0;
  for (const PhaseTiming& timing : timings) total += timing.seconds;
  return total;
}

}  // namespace harmonia
