// Choosing a backend and a system solver.

#include "solve/backend_selection.h"

#include "backend/iterative_system_solver.h"
#include "fallback/cpu_backend.h"
#include "fallback/direct_solvers.h"
#include "solve/cross_check_backend.h"

#ifdef HARMONIA_HAVE_VULKAN
#include "harmonia/vulkan_context.h"
#include "kernels/context_impl.h"
#include "kernels/vulkan_backend.h"
#endif

namespace harmonia::detail {
namespace {

void set_message(std::string* message, std::string text) {
  if (message != nullptr) *message = std::move(text);
}

#ifdef HARMONIA_HAVE_VULKAN
// A Vulkan backend on the caller's context, or on a new one; nullptr and `reason` on failure.
std::unique_ptr<Backend> make_vulkan_backend(const SolverOptions& options, bool hardware_only,
                                             std::string& reason) {
  try {
    std::shared_ptr<vulkan::Context> context = options.vulkan_context;
    // A context whose device was lost stays lost (every submission would fail).
    if (context && context->impl().device_lost())
      throw Error(Status::device_failure,
                  "the Vulkan device of the given context (" + context->device().name +
                      ") was lost");
    if (!context) {
      vulkan::ContextOptions context_options;
      context_options.hardware_only = hardware_only;
      context_options.enable_float64 = options.device_precision == DevicePrecision::float64;
      context = std::make_shared<vulkan::Context>(vulkan::Context::create(context_options));
    }
    return std::make_unique<vulkan::detail::VulkanBackend>(std::move(context),
                                                           options.device_precision);
  } catch (const Error& error) {
    reason = error.what();
    return nullptr;
  }
}
#endif

// The backend for the choice, before any cross-checking.
std::unique_ptr<Backend> make_plain_backend(const SolverOptions& options, std::string* message) {
  set_message(message, {});
  switch (options.backend) {
    case BackendChoice::cpu:
      return std::make_unique<CpuBackend>();
    case BackendChoice::automatic: {
#ifdef HARMONIA_HAVE_VULKAN
      std::string reason;
      if (auto backend = make_vulkan_backend(options, true, reason)) return backend;
      if (options.vulkan_context && options.vulkan_context->impl().device_lost())
        set_message(message, reason + "; using the CPU backend (" + CpuBackend().description() +
                                 ")");
      else
        set_message(message, "no hardware Vulkan device (" + reason +
                                 "); using the CPU backend (" + CpuBackend().description() + ")");
#else
      set_message(message, "no Vulkan backend in this build; using the CPU backend (" +
                               CpuBackend().description() + ")");
#endif
      return std::make_unique<CpuBackend>();
    }
    case BackendChoice::vulkan: {
#ifdef HARMONIA_HAVE_VULKAN
      std::string reason;
      if (auto backend = make_vulkan_backend(options, false, reason)) return backend;
      set_message(message, "the Vulkan backend is unavailable: " + reason +
                               "; use --backend cpu (BackendChoice::cpu)");
#else
      set_message(message,
                  "this build has no Vulkan backend (configured with HARMONIA_WITH_VULKAN=OFF); "
                  "use --backend cpu");
#endif
      return nullptr;
    }
  }
  return nullptr;
}

}  // namespace

std::unique_ptr<Backend> make_backend(const SolverOptions& options, std::string* message) {
  std::unique_ptr<Backend> backend = make_plain_backend(options, message);
  // Cross-checking compares against the CPU backend: a CPU backend is not compared with itself.
  if (backend && options.cross_check && backend->kind() != BackendKind::cpu)
    return std::make_unique<CrossCheckBackend>(std::move(backend));
  return backend;
}

std::unique_ptr<Backend> make_backend(BackendChoice choice, std::string* message) {
  SolverOptions options;
  options.backend = choice;
  return make_backend(options, message);
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

bool may_retry_on_cpu(BackendChoice choice, const Backend& backend, const SolveStats& failed) {
  const bool device_trouble = failed.status == Status::not_converged ||
                              failed.status == Status::numerical_failure ||
                              failed.status == Status::device_failure;
  return device_trouble && choice == BackendChoice::automatic && backend.kind() != BackendKind::cpu;
}

std::string cpu_retry_notice(const std::string& device_solver, const SolveStats& failed, const Backend& cpu) {
  return "the device's " + device_solver + " failed (" + failed.message + "); solved on the CPU (" +
         cpu.description() + ") instead";
}

}  // namespace harmonia::detail
