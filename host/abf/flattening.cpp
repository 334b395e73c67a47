#include "harmonia/flattening.h"

#include <stdexcept>
#include <string>

#include "harmonia/fixed_boundary_map.h"
#include "harmonia/free_boundary_map.h"
#include "harmonia/linear_abf.h"
#include "harmonia/lscm.h"
#include "harmonia/quasi_harmonic_map.h"

namespace harmonia {

namespace {

constexpr FlatteningMethod kMethods[] = {FlatteningMethod::conformal, FlatteningMethod::lscm,
                                         FlatteningMethod::qhm,       FlatteningMethod::abf,
                                         FlatteningMethod::linabf,    FlatteningMethod::free};

// Chapter 5 defines the tensor form of two schemes: cotangent (5.10) and mean value (5.4).
QuasiHarmonicWeights tensor_weights(const FlatteningChoice& choice) {
  if (choice.weights == WeightScheme::cotangent) return QuasiHarmonicWeights::tensor_cotangent;
  if (choice.weights == WeightScheme::mean_value) return QuasiHarmonicWeights::tensor_mean_value;
  throw std::invalid_argument(std::string(to_string(choice.method)) +
                              " supports the cotangent and mean-value weights only");
}

}  // namespace

std::string_view to_string(FlatteningMethod method) {
  switch (method) {
    case FlatteningMethod::conformal:
      return "conformal";
    case FlatteningMethod::lscm:
      return "lscm";
    case FlatteningMethod::qhm:
      return "qhm";
    case FlatteningMethod::abf:
      return "abf";
    case FlatteningMethod::linabf:
      return "linabf";
    case FlatteningMethod::free:
      return "free";
  }
  return "unknown";  // Unreachable: -Werror=switch keeps the list above complete.
}

std::optional<FlatteningMethod> flattening_method_from_string(std::string_view name) {
  for (const FlatteningMethod method : kMethods)
    if (to_string(method) == name) return method;
  return std::nullopt;
}

MapResult flatten_disk(const Mesh& mesh, const FlatteningChoice& choice, const SolverOptions& solver,
                       AngleFigures* angle_figures) {
  // The angle-based methods return their angles too; the caller may keep the energy and t.
  const auto keep_map = [angle_figures](AngleMapResult&& result) {
    if (angle_figures) *angle_figures = {result.abf_energy, result.boundary_t};
    return MapResult{std::move(result.uv), std::move(result.report)};
  };
  switch (choice.method) {
    case FlatteningMethod::conformal: {
      FixedBoundaryOptions options;
      options.weights = choice.weights;
      options.boundary.shape = choice.boundary;
      options.solver = solver;
      options.normalization = choice.normalization;
      return fixed_boundary_map(mesh, options);
    }
    case FlatteningMethod::lscm: {
      LscmOptions options;
      options.solver = solver;
      options.normalization = choice.normalization;
      return lscm(mesh, options);
    }
    case FlatteningMethod::qhm: {
      QuasiHarmonicOptions options;
      options.weights = tensor_weights(choice);
      options.boundary.shape = choice.boundary;
      options.max_rounds = choice.rounds;
      options.solver = solver;
      options.normalization = choice.normalization;
      QuasiHarmonicResult result = quasi_harmonic_map(mesh, options);
      return MapResult{std::move(result.uv), std::move(result.report)};
    }
    case FlatteningMethod::free: {
      FreeBoundaryOptions options;
      options.weights = tensor_weights(choice);
      options.polish = choice.polish;
      options.stop_after = choice.stop_after_conformal ? FreeBoundaryStop::conformal
                                                       : FreeBoundaryStop::quasi_harmonic;
      options.solver = solver;
      options.normalization = choice.normalization;
      FreeBoundaryResult result = free_boundary_map(mesh, options);
      return MapResult{std::move(result.uv), std::move(result.report)};
    }
    case FlatteningMethod::abf: {
      AbfOptions options;
      options.boundary_t = choice.boundary_t;
      options.solver = choice.abf_solver;
      options.underdetermined = choice.underdetermined;
      options.reconstruction.method = choice.reconstruction;
      options.reconstruction.normalization = choice.normalization;
      options.solver_options = solver;
      return keep_map(abf(mesh, options));
    }
    case FlatteningMethod::linabf: {
      LinearAbfOptions options;
      options.rounds = choice.linabf_rounds;
      options.reconstruction.method = choice.reconstruction;
      options.reconstruction.normalization = choice.normalization;
      options.solver_options = solver;
      return keep_map(linear_abf(mesh, options));
    }
  }
  throw std::invalid_argument("unknown method");
}

}  // namespace harmonia
