#include "core/released_call.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "core/errors.h"

namespace harmonia::python {

namespace {

// How often the waiting thread looks at the cancel event and at signals when no progress comes.
constexpr auto kPoll = std::chrono::milliseconds(20);

// Where a phase moves the fraction. With shares, a listed phase moves it to its start plus its
// share times its own step / total, and an unlisted one keeps it. Without shares (a pipeline whose
// phases' times vary too much with the mesh to weigh), each new phase halves the distance to 1.
class FractionScale {
 public:
  explicit FractionScale(const PhaseShares& shares) : shares_(shares) {}

  double fraction(const Progress& progress) {
    if (shares_.empty()) {
      if (progress.stage != last_stage_) {
        if (!last_stage_.empty()) last_ += (1.0 - last_) / 2;
        last_stage_ = progress.stage;
      }
      return last_;
    }
    double start = 0.0;
    for (const auto& [phase, share] : shares_) {
      if (phase == progress.stage) {
        const double within = progress.total > 0 ? std::clamp(double(progress.step) / progress.total, 0.0, 1.0) : 0.0;
        last_ = std::max(last_, std::min(1.0, start + share * within));
        return last_;
      }
      start += share;
    }
    return last_;
  }

 private:
  const PhaseShares& shares_;
  double last_ = 0.0;
  std::string last_stage_;
};

// Shared by the worker (which records reports) and the waiting caller (which hands them on).
struct Exchange {
  std::mutex mutex;
  std::condition_variable changed;
  std::optional<std::pair<std::string, double>> report;  // the latest report not yet handed on
  bool finished = false;
  std::atomic<bool> cancel{false};
};

}  // namespace

PythonControl python_control(py::object progress, py::object cancel) {
  if (!progress.is_none() && !PyCallable_Check(progress.ptr()))
    raise_invalid_input("progress is not callable: expected a function (phase, fraction) -> bool");
  if (!cancel.is_none() && !py::hasattr(cancel, "is_set"))
    raise_invalid_input("cancel has no is_set(): expected a threading.Event");
  return PythonControl{std::move(progress), std::move(cancel)};
}

void run_released(const PythonControl& control, const PhaseShares& shares,
                  const std::function<bool(const ProgressCallback&)>& work) {
  Exchange exchange;
  FractionScale scale(shares);
  // Called by the library, on its threads, without the lock: records and wakes the caller.
  const ProgressCallback record = [&exchange, &scale](const Progress& progress) {
    {
      const std::lock_guard lock(exchange.mutex);
      exchange.report.emplace(std::string(progress.stage), scale.fraction(progress));
    }
    exchange.changed.notify_one();
    return !exchange.cancel.load();
  };
  std::exception_ptr thrown;
  bool succeeded = false;
  std::thread worker([&] {
    try {
      succeeded = work(record);
    } catch (...) {
      thrown = std::current_exception();
    }
    {
      const std::lock_guard lock(exchange.mutex);
      exchange.finished = true;
    }
    exchange.changed.notify_one();
  });
  std::optional<py::error_already_set> python_error;
  for (bool finished = false; !finished;) {
    std::optional<std::pair<std::string, double>> report;
    {
      const py::gil_scoped_release released;
      std::unique_lock lock(exchange.mutex);
      exchange.changed.wait_for(lock, kPoll, [&] { return exchange.report || exchange.finished; });
      report = std::exchange(exchange.report, std::nullopt);
      finished = exchange.finished;
    }
    if (python_error) continue;  // already cancelled: wait for the call to end
    try {
      if (report && !control.progress.is_none()) {
        const py::object answer = control.progress(report->first, report->second);
        if (answer.ptr() == Py_False) exchange.cancel = true;
      }
      if (!control.cancel.is_none() && control.cancel.attr("is_set")().cast<bool>()) exchange.cancel = true;
      if (PyErr_CheckSignals() != 0) throw py::error_already_set();
    } catch (py::error_already_set& error) {
      python_error.emplace(std::move(error));
      exchange.cancel = true;
    }
  }
  {
    const py::gil_scoped_release released;
    worker.join();
  }
  if (python_error) throw std::move(*python_error);
  if (thrown) std::rethrow_exception(thrown);
  if (succeeded && !control.progress.is_none()) control.progress("done", 1.0);
}

}  // namespace harmonia::python
