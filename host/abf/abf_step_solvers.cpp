// Choosing the linear solver of an ABF Newton step, and the fast one: the reduced system of
// ABF++ (triangle rows eliminated face by face; abf/reduced_angle_system.h), factorized by
// CHOLMOD on the CPU and solved by PCG on devices.

#include <string>
#include <utility>
#include <vector>

#include "abf/abf_step_solvers.h"
#include "abf/reduced_angle_system.h"
#include "solve/backend_selection.h"

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

namespace {

// A device's step solver that hands the steps to the CPU once a device solve fails in a way the
// CPU can make good (make_abf_step_solver's `cpu_retry`).
class CpuRetryStep final : public AbfStepSolver {
 public:
  CpuRetryStep(std::unique_ptr<AbfStepSolver> device_step, Backend& device, AbfSolver choice,
               const AngleTopology& topology, const IterativeSettings& settings,
               const ProgressCallback& progress)
      : device_step_(std::move(device_step)), device_(device), choice_(choice), topology_(topology),
        settings_(settings), progress_(progress) {}

  SolveStats solve(const RowMajorSparse& jacobian, const Eigen::VectorXd& hessian,
                   const Eigen::VectorXd& r, const Eigen::VectorXd& s, Eigen::VectorXd& dx,
                   Eigen::VectorXd& lambda) override {
    if (cpu_step_) return cpu_step_->solve(jacobian, hessian, r, s, dx, lambda);
    const Eigen::VectorXd warm_start = lambda;
    const SolveStats stats = device_step_->solve(jacobian, hessian, r, s, dx, lambda);
    if (usable_step(stats) || !may_retry_on_cpu(BackendChoice::automatic, device_, stats)) return stats;
    cpu_backend_ = make_backend(BackendChoice::cpu, nullptr);
    cpu_step_ = make_abf_step_solver(choice_, *cpu_backend_, topology_, settings_, progress_, nullptr);
    if (!cpu_step_) return stats;  // every choice exists on the CPU; kept for safety
    lambda = warm_start;
    SolveStats retried = cpu_step_->solve(jacobian, hessian, r, s, dx, lambda);
    retried.iterations += stats.iterations;
    if (usable_step(retried)) notice_ = cpu_retry_notice(device_step_->name(), stats, *cpu_backend_);
    return retried;
  }

  std::string name() const override {
    return cpu_step_ ? cpu_step_->name() + " (after the device's " + device_step_->name() + " failed)"
                     : device_step_->name();
  }

  std::string take_cpu_retry_notice() override { return std::exchange(notice_, {}); }

 private:
  std::unique_ptr<AbfStepSolver> device_step_;
  Backend& device_;
  AbfSolver choice_;
  const AngleTopology& topology_;
  IterativeSettings settings_;
  ProgressCallback progress_;
  std::unique_ptr<Backend> cpu_backend_;
  std::unique_ptr<AbfStepSolver> cpu_step_;
  std::string notice_;
};

// The solver for `choice` on `backend`, without the CPU retry.
std::unique_ptr<AbfStepSolver> make_step_solver(AbfSolver choice, Backend& backend, const AngleTopology& topology,
                                                const IterativeSettings& settings, const ProgressCallback& progress,
                                                std::string* error, std::vector<int> vertex_ordering) {
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

}  // namespace

std::unique_ptr<AbfStepSolver> make_abf_step_solver(AbfSolver choice, Backend& backend,
                                                    const AngleTopology& topology,
                                                    const IterativeSettings& settings,
                                                    const ProgressCallback& progress,
                                                    std::string* error,
                                                    std::vector<int> vertex_ordering, bool cpu_retry) {
  std::unique_ptr<AbfStepSolver> step =
      make_step_solver(choice, backend, topology, settings, progress, error, std::move(vertex_ordering));
  if (!step || !cpu_retry || backend.kind() == BackendKind::cpu) return step;
  return std::make_unique<CpuRetryStep>(std::move(step), backend, choice, topology, settings, progress);
}

}  // namespace harmonia::detail
