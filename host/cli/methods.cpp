#include "cli/methods.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <stdexcept>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/free_boundary_map.h"
#include "harmonia/linear_abf.h"
#include "harmonia/lscm.h"
#include "harmonia/quasi_harmonic_map.h"
#ifdef HARMONIA_HAVE_VULKAN
#include "harmonia/vulkan_context.h"
#endif

namespace harmonia::cli {

std::string to_string(MethodKind method) {
  switch (method) {
    case MethodKind::conformal:
      return "conformal";
    case MethodKind::lscm:
      return "lscm";
    case MethodKind::qhm:
      return "qhm";
    case MethodKind::abf:
      return "abf";
    case MethodKind::linabf:
      return "linabf";
    case MethodKind::free:
      return "free";
  }
  return "unknown";  // Unreachable: -Werror=switch keeps the list above complete.
}

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

// Chapter 5 defines the tensor form of two schemes: cotangent (5.10) and mean value (5.4).
QuasiHarmonicWeights tensor_weights(const MethodChoice& choice) {
  if (choice.weights == WeightScheme::cotangent) return QuasiHarmonicWeights::tensor_cotangent;
  if (choice.weights == WeightScheme::mean_value) return QuasiHarmonicWeights::tensor_mean_value;
  throw std::invalid_argument(to_string(choice.method) +
                              " supports the cotangent and mean-value weights only");
}

SolverOptions solver_options(const MethodChoice& choice, const ProgressCallback& progress) {
  return program_solver_options(choice.backend, progress);
}

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

BackendChoice backend_choice(const std::string& name) {
  if (name == "cpu") return BackendChoice::cpu;
  if (name == "vulkan") return BackendChoice::vulkan;
  return BackendChoice::automatic;
}

MapResult run_method(const Mesh& mesh, const MethodChoice& choice,
                     const ProgressCallback& progress, AngleFigures* angle_figures) {
  // The angle-based methods return their angles too; the CLI keeps the energy and t.
  const auto keep_map = [angle_figures](AngleMapResult&& result) {
    if (angle_figures) *angle_figures = {result.abf_energy, result.boundary_t};
    return MapResult{std::move(result.uv), std::move(result.report)};
  };
  switch (choice.method) {
    case MethodKind::conformal: {
      FixedBoundaryOptions options;
      options.weights = choice.weights;
      options.boundary.shape = choice.boundary;
      options.solver = solver_options(choice, progress);
      options.normalization = choice.normalization;
      return fixed_boundary_map(mesh, options);
    }
    case MethodKind::lscm: {
      LscmOptions options;
      options.solver = solver_options(choice, progress);
      options.normalization = choice.normalization;
      return lscm(mesh, options);
    }
    case MethodKind::qhm: {
      QuasiHarmonicOptions options;
      options.weights = tensor_weights(choice);
      options.boundary.shape = choice.boundary;
      options.max_rounds = choice.rounds;
      options.solver = solver_options(choice, progress);
      options.normalization = choice.normalization;
      QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
      return MapResult{std::move(result.uv), std::move(result.report)};
    }
    case MethodKind::free: {
      FreeBoundaryOptions options;
      options.weights = tensor_weights(choice);
      options.polish = choice.polish;
      options.stop_after = choice.stop_after_conformal ? FreeBoundaryStop::conformal
                                                       : FreeBoundaryStop::quasi_harmonic;
      options.solver = solver_options(choice, progress);
      options.normalization = choice.normalization;
      FreeBoundaryResult result = free_boundary_map(mesh, options);
      return MapResult{std::move(result.uv), std::move(result.report)};
    }
    case MethodKind::abf: {
      AbfOptions options;
      options.boundary_t = choice.boundary_t;
      options.solver = choice.abf_solver;
      options.underdetermined = choice.underdetermined;
      options.reconstruction.method = choice.reconstruction;
      options.reconstruction.normalization = choice.normalization;
      options.solver_options = solver_options(choice, progress);
      return keep_map(abf(mesh, options));
    }
    case MethodKind::linabf: {
      LinearAbfOptions options;
      options.rounds = choice.linabf_rounds;
      options.reconstruction.method = choice.reconstruction;
      options.reconstruction.normalization = choice.normalization;
      options.solver_options = solver_options(choice, progress);
      return keep_map(linear_abf(mesh, options));
    }
  }
  throw std::invalid_argument("unknown method");
}

}  // namespace harmonia::cli
