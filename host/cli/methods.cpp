#include "cli/methods.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>

#ifdef HARMONIA_HAVE_VULKAN
#include "harmonia/vulkan_context.h"
#endif

namespace harmonia::cli {

namespace {

#ifdef HARMONIA_HAVE_VULKAN
// $HARMONIA_VULKAN_DEVICE picks the Vulkan device for --backend vulkan and auto: an index in the
// loader's order, or text the device name contains (docs/vulkan.md, "Choosing the device"). The
// program reads it; the library never reads the environment.
std::shared_ptr<vulkan::Context> context_from_environment(BackendChoice backend) {
  const char* wanted = std::getenv("HARMONIA_VULKAN_DEVICE");
  if (backend == BackendChoice::cpu || wanted == nullptr || *wanted == '\0') return nullptr;
  const std::string text = wanted;
  vulkan::ContextOptions options;
  if (std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); }))
    options.device_index = std::stoi(text);
  else
    options.device_name = text;
  return std::make_shared<vulkan::Context>(vulkan::Context::create(options));
}
#endif

}  // namespace

SolverOptions program_solver_options(BackendChoice backend, const ProgressCallback& progress) {
  SolverOptions solver;
  solver.backend = backend;
  solver.progress = progress;
#ifdef HARMONIA_HAVE_VULKAN
  solver.vulkan_context = context_from_environment(backend);
#endif
  return solver;
}

IterativePreconditioner preconditioner_choice(const std::string& name) {
  return name == "jacobi" ? IterativePreconditioner::jacobi : IterativePreconditioner::multilevel;
}

const char* const preconditioner_help =
    "Preconditioner of the device's conjugate gradients: multilevel (default, smoothed-aggregation "
    "multigrid) or jacobi (the diagonal)";

BackendChoice backend_choice(const std::string& name) {
  if (name == "cpu") return BackendChoice::cpu;
  if (name == "vulkan") return BackendChoice::vulkan;
  return BackendChoice::automatic;
}

MapResult run_method(const Mesh& mesh, const MethodChoice& choice,
                     const ProgressCallback& progress, AngleFigures* angle_figures) {
  SolverOptions solver = program_solver_options(choice.backend, progress);
  solver.preconditioner = choice.preconditioner;
  return flatten_disk(mesh, choice, solver, angle_figures);
}

}  // namespace harmonia::cli
