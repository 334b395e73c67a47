#pragma once
// Internal: choosing the backend from a method's SolverOptions (backend choice and, with Vulkan,
// the caller's context), and the system solver that suits a backend. This is where the backend
// interface (backend/backend.h) meets its two implementations (fallback/, kernels/).

#include <memory>
#include <string>

#include "backend/backend.h"
#include "harmonia/solver_options.h"

namespace harmonia::detail {

// The backend for options.backend (docs/vulkan.md, "Choosing the device"):
//   cpu       -> the CPU backend.
//   vulkan    -> options.vulkan_context if given, else a context harmonia creates on the best
//                device of any kind (a software device such as lavapipe included). Without a
//                loader or device: nullptr and `message` says why.
//   automatic -> options.vulkan_context if given; else a hardware GPU (discrete or integrated) if
//                one exists; otherwise the CPU backend, with `message` saying why. A software
//                Vulkan device is never chosen automatically: it is slower than the CPU backend.
//                A given context whose device was lost (device loss or a hang, reported as
//                Status::device_failure before) falls back to the CPU backend with a message.
// With options.cross_check, a Vulkan backend is wrapped in a CrossCheckBackend
// (solve/cross_check_backend.h); a CPU backend is not (there is nothing to compare it with, and
// its cross_check_error() is 0).
[[nodiscard]] std::unique_ptr<Backend> make_backend(const SolverOptions& options,
                                                    std::string* message);

// Creates a solver for matrices of `kind` on `backend`: a direct factorization where the backend
// supports it (CPU), else the matching Krylov method on the backend's primitives.
[[nodiscard]] std::unique_ptr<SparseSystemSolver> make_system_solver(
    Backend& backend, MatrixKind kind, const IterativeSettings& settings,
    const ProgressCallback& progress);

// Whether a device solve's failure is one the CPU can make good (docs/vulkan.md, "When a device
// solve fails"): the iteration cap, a non-finite residual, a lost device. With the backend left
// to harmonia (BackendChoice::automatic) such a system is factorized and solved on the CPU
// instead, once, and stays there; a caller who asked for the device gets the failure.
[[nodiscard]] bool may_retry_on_cpu(BackendChoice choice, const Backend& backend, const SolveStats& failed);

// The notice of such a move, for SolveReport::fallbacks: "the device's pcg-multilevel failed
// (<its message>); solved on the CPU (<cpu's description>) instead".
[[nodiscard]] std::string cpu_retry_notice(const std::string& device_solver, const SolveStats& failed,
                                           const Backend& cpu);

// The backend a method should use for `choice`. Returns nullptr and fills `message` when the choice
// cannot be honoured (e.g. vulkan in a build without it). For `automatic` without a device, returns
// the CPU backend and sets `message` to the one-line fallback notice.
[[nodiscard]] std::unique_ptr<Backend> make_backend(BackendChoice choice, std::string* message);

}  // namespace harmonia::detail
