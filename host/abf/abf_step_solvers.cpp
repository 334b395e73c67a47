// Choosing the linear solver of an ABF Newton step, and the fast one: the reduced system of
// ABF++ (triangle rows eliminated face by face; abf/reduced_angle_system.h), factorized by
// CHOLMOD on the CPU and solved by PCG on devices.

#include <string>
#include <utility>
#include <vector>

#include "abf/abf_step_solvers.h"
#include "abf/reduced_angle_system.h"

namespace harmonia::detail {
namespace {

// ReducedAngleSystem solves [W^-1 J^T; J 0] [dx; lambda] = [r; s] with W = H^-1: exactly the
// Newton system with the diagonal Hessian H.
class ReducedStep final : public AbfStepSolver {
 public:
  ReducedStep(Backend& backend, const AngleTopology& topology, const IterativeSettings& settings,
              const ProgressCallback& progress, std::vector<int> vertex_ordering)
      : system_(backend, topology, settings, progress) {
    if (!vertex_ordering.empty()) system_.use_vertex_ordering(std::move(vertex_ordering));
  }

  SolveStats solve(const RowMajorSparse& jacobian, const Eigen::VectorXd& hessian,
                   const Eigen::VectorXd& r, const Eigen::VectorXd& s, Eigen::VectorXd& dx,
                   Eigen::VectorXd& lambda) override {
    return system_.solve(jacobian, hessian.cwiseInverse(), r, s, dx, lambda);
  }

  [[nodiscard]] std::string name() const override { return system_.solver_name(); }

 private:
  ReducedAngleSystem system_;
};

}  // namespace

std::unique_ptr<AbfStepSolver> make_abf_step_solver(AbfSolver choice, Backend& backend,
                                                    const AngleTopology& topology,
                                                    const IterativeSettings& settings,
                                                    const ProgressCallback& progress,
                                                    std::string* error,
                                                    std::vector<int> vertex_ordering) {
  switch (choice) {
    case AbfSolver::automatic:
      // The reduced system picks CHOLMOD on the CPU and PCG on devices itself.
      return std::make_unique<ReducedStep>(backend, topology, settings, progress,
                                           std::move(vertex_ordering));
    case AbfSolver::schur_direct:
      if (!backend.supports(Feature::direct_factorization)) {
        if (error)
          *error = "abf: the schur_direct solver needs a direct factorization, which the " +
                   backend.description() +
                   " backend does not have (use automatic, schur_minres or uzawa)";
        return nullptr;
      }
      return std::make_unique<ReducedStep>(backend, topology, settings, progress,
                                           std::move(vertex_ordering));
    case AbfSolver::schur_minres:
      return make_schur_minres_step(backend, settings, progress);
    case AbfSolver::uzawa:
      return make_uzawa_step(backend, settings, progress);
    case AbfSolver::full_minres:
      return make_full_minres_step(backend, settings, progress);
    case AbfSolver::full_cgnr:
      return make_full_cgnr_step(backend, settings, progress);
  }
  if (error) *error = "abf: unknown solver";
  return nullptr;
}

}  // namespace harmonia::detail
