// Removing unfinished outputs when the program is interrupted (harmonia/io.h): SIGINT and SIGTERM
// handlers that remove the named new files being written (atomic_file.h), then let the signal end
// the process as it would have. Installed only when a program asks: handlers are process-wide.

#include <signal.h>

#include "harmonia/io.h"
#include "io/atomic_file.h"

namespace harmonia {
namespace {

extern "C" void remove_unfinished_outputs_then_die(int signal_number) {
  detail::remove_unfinished_outputs();
  // SA_RESETHAND restored the default action, and the signal is blocked until this handler
  // returns: raised again, it then ends the process, whose status still names it.
  ::raise(signal_number);
}

}  // namespace

void remove_unfinished_outputs_on_signals() {
  struct sigaction action {};
  action.sa_handler = remove_unfinished_outputs_then_die;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  for (const int signal_number : {SIGINT, SIGTERM}) ::sigaction(signal_number, &action, nullptr);
}

}  // namespace harmonia
