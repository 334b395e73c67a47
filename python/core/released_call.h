#pragma once
// Running a library call with the global interpreter lock released, with progress and
// cancellation from Python.
//
// The call runs on a worker thread of its own; the calling thread waits for it without the lock.
// Whenever the library reports progress, the calling thread takes the lock and calls the Python
// `progress(phase, fraction)` itself: Python code only ever runs on the thread that made the
// call, never on the library's workers, so a callback that updates a progress bar, or raises,
// cannot deadlock or race with them. Between reports (at least every kPollSeconds) it looks at
// the `cancel` event and at pending signals (Ctrl+C). A callback returning False, a set event, an
// exception in the callback or a KeyboardInterrupt cancel the call: the library's next progress
// check returns false and the call ends with Status::cancelled, having changed nothing. Without
// `progress` and `cancel` the call runs the same way, so that Ctrl+C stops it too.
//
// The fraction only rises, from 0 to a final call with ("done", 1.0) after a call that succeeded.
// Where the caller knows the phases' usual shares of the time (PhaseShares) the fraction follows
// them, and a phase it does not list keeps the fraction where it is; without shares each new
// phase halves the distance to 1.

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <pybind11/pybind11.h>

#include "harmonia/types.h"

namespace harmonia::python {

namespace py = pybind11;

//! The usual share of a call's time of each of its phases, in order (the shares need not sum
//! to one: alternative phases, such as the device's and the CPU's, may both be listed).
using PhaseShares = std::vector<std::pair<std::string, double>>;

//! What the Python caller passed for progress and cancellation (either may be None).
struct PythonControl {
  py::object progress;  //!< callable(phase: str, fraction: float) -> bool | None
  py::object cancel;    //!< an object with is_set() (threading.Event), or None
};

//! Checks the types of `progress` and `cancel` (raises InvalidInputError naming the argument).
[[nodiscard]] PythonControl python_control(py::object progress, py::object cancel);

//! Runs `work(callback)` with the lock released; rethrows what it threw (a C++ exception, or the
//! Python exception the progress callback raised). `work` returns whether the call succeeded
//! (then progress hears ("done", 1.0) last). Called with the lock held; `work` must not touch
//! Python objects.
void run_released(const PythonControl& control, const PhaseShares& shares,
                  const std::function<bool(const ProgressCallback&)>& work);

}  // namespace harmonia::python
