// Choosing a backend and a system solver.

#include "detail/backend.h"
#include "detail/iterative_system_solver.h"
#include "fallback/cpu_backend.h"
#include "fallback/direct_solvers.h"

namespace harmonia::detail {

std::unique_ptr<Backend> make_backend(BackendChoice choice, std::string* message) {
  if (message != nullptr) message->clear();
  switch (choice) {
    case BackendChoice::cpu:
      return std::make_unique<CpuBackend>();
    case BackendChoice::automatic:
      // Vulkan hook: when the Vulkan backend (kernels/) exists, try it here first and fall back
      // to the CPU with the notice below only when no device is found.
      if (message != nullptr)
        *message = "no Vulkan backend in this build; using the CPU backend (" +
                   CpuBackend().description() + ")";
      return std::make_unique<CpuBackend>();
    case BackendChoice::vulkan:
      if (message != nullptr)
        *message =
            "this build has no Vulkan backend (the Vulkan backend is a separate component); "
            "use --backend cpu";
      return nullptr;
  }
  return nullptr;
}

std::unique_ptr<SparseSystemSolver> make_system_solver(Backend& backend, MatrixKind kind,
                                                       const IterativeSettings& settings,
                                                       const ProgressCallback& progress) {
  if (backend.supports(Feature::direct_factorization)) {
    // LDLT without pivoting is unsafe for indefinite matrices: those go to LU like general ones.
    if (kind == MatrixKind::symmetric_positive_definite) return make_cholesky_solver();
    return make_lu_solver();
  }
  return make_iterative_solver(backend, kind, settings, progress);
}

}  // namespace harmonia::detail
