// The non-template half of harmonia/async.h: the cancellation hook and the submission observer.

#include "harmonia/async.h"

#ifdef HARMONIA_HAVE_VULKAN
#include "harmonia/vulkan_context.h"
#include "kernels/context_impl.h"
#endif

namespace harmonia::detail {

SolverOptions cancellable_options(const SolverOptions& solver,
                                  std::shared_ptr<TaskControl> control) {
  SolverOptions options = solver;
  // Asked before and after the application's callback, so that a cancel() issued while that
  // callback runs stops the map at this very check.
  options.progress = [control = std::move(control),
                      own = solver.progress](const Progress& progress) {
    if (control->cancel_requested()) return false;
    if (own && !own(progress)) return false;
    return !control->cancel_requested();
  };
  return options;
}

TaskScope::TaskScope(TaskControl& control, const SolverOptions& options) : control_(control) {
#ifdef HARMONIA_HAVE_VULKAN
  if (options.vulkan_context) {
    auto observer = std::make_shared<vulkan::detail::SubmissionObserver>();
    observer->context = &options.vulkan_context->impl();
    observer->value = &control.signal_value_slot();
    vulkan::detail::observe_submissions(observer.get());
    observation_ = std::move(observer);
  }
#else
  (void)options;
#endif
}

TaskScope::~TaskScope() {
#ifdef HARMONIA_HAVE_VULKAN
  if (observation_) vulkan::detail::observe_submissions(nullptr);
#endif
  control_.mark_finished();
}

}  // namespace harmonia::detail
