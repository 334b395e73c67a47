#include "cli/methods.h"

#include <stdexcept>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/lscm.h"
#include "harmonia/quasi_harmonic_map.h"

namespace harmonia::cli {

std::string to_string(MethodKind method) {
  switch (method) {
    case MethodKind::conformal:
      return "conformal";
    case MethodKind::lscm:
      return "lscm";
    case MethodKind::qhm:
      return "qhm";
  }
  return "unknown";  // Unreachable: -Werror=switch keeps the list above complete.
}

namespace {

SolverOptions solver_options(const MethodChoice& choice, const ProgressCallback& progress) {
  SolverOptions solver;
  solver.backend = choice.backend;
  solver.progress = progress;
  return solver;
}

}  // namespace

MapResult run_method(const Mesh& mesh, const MethodChoice& choice,
                     const ProgressCallback& progress) {
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
      // Chapter 5 defines the tensor form of two schemes: cotangent (5.10) and mean value (5.4).
      if (choice.weights == WeightScheme::cotangent) {
        options.weights = QuasiHarmonicWeights::tensor_cotangent;
      } else if (choice.weights == WeightScheme::mean_value) {
        options.weights = QuasiHarmonicWeights::tensor_mean_value;
      } else {
        throw std::invalid_argument("qhm supports the cotangent and mean-value weights only");
      }
      options.boundary.shape = choice.boundary;
      options.max_rounds = choice.rounds;
      options.solver = solver_options(choice, progress);
      options.normalization = choice.normalization;
      QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
      return MapResult{std::move(result.uv), std::move(result.report)};
    }
  }
  throw std::invalid_argument("unknown method");
}

}  // namespace harmonia::cli
