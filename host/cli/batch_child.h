#pragma once
//! \file batch_child.h
//! \brief Child processes for `harmonia batch`: each input runs in a process of its own (this same
//! program, started again with one command), so that a crash, an abort or running out of memory
//! ends only that child; and the Ctrl-C watch that stops them.

#include <sys/types.h>

#include <chrono>
#include <string>
#include <vector>

namespace harmonia::cli {

//! How a child ended and what it printed.
struct FinishedChild {
  int tag = 0;         //!< The caller's number for it (given to ChildPool::start).
  int exit_code = -1;  //!< Its exit status, when it exited (-1 when a signal ended it).
  int signal = 0;      //!< The signal that ended it, or 0.
  std::string standard_output;
  std::string standard_error;
  double seconds = 0.0;  //!< Wall-clock seconds from its start to its end.
};

//! The exit status of a child whose program could not be started (the shell's "not found").
inline constexpr int kChildCouldNotStart = 127;

//! "SIGSEGV": a signal's name, for the log.
[[nodiscard]] std::string signal_name(int signal_number);
//! "SIGSEGV (Segmentation fault)": its name and what it means.
[[nodiscard]] std::string signal_description(int signal_number);

//! Runs child processes of one program side by side, each with its standard output and error
//! captured through pipes (read as they come, so that a child never blocks on a full pipe).
class ChildPool {
 public:
  //! `program`: the executable every child runs (e.g. /proc/self/exe, this very program).
  explicit ChildPool(std::string program);
  //! Ends the children still running (terminate_all).
  ~ChildPool();
  ChildPool(const ChildPool&) = delete;
  ChildPool& operator=(const ChildPool&) = delete;

  //! Starts the program with `arguments` (argv, its name first) and the parent's environment
  //! with the `NAME=value` entries of `environment` set. Throws std::system_error when no pipe
  //! or process can be made. A program that cannot be executed ends with kChildCouldNotStart.
  void start(int tag, const std::vector<std::string>& arguments,
             const std::vector<std::string>& environment);

  [[nodiscard]] std::size_t running() const { return children_.size(); }

  //! Reads what the children print until one or more have ended, `timeout` has passed or a
  //! signal arrived; returns those that ended (perhaps none).
  [[nodiscard]] std::vector<FinishedChild> wait(std::chrono::milliseconds timeout);

  //! Sends SIGTERM to every running child and waits for them (they remove their unfinished
  //! outputs and end); nothing of theirs is returned.
  void terminate_all();

 private:
  struct Running {
    int tag = 0;
    pid_t pid = -1;
    int output_pipe = -1;  // Read ends; -1 once at end of file.
    int error_pipe = -1;
    std::string standard_output;
    std::string standard_error;
    std::chrono::steady_clock::time_point start;
  };
  static void read_available(int& pipe, std::string& into);
  static FinishedChild reap(Running& child);

  std::string program_;
  std::vector<Running> children_;
};

//! While it exists, SIGINT and SIGTERM do not end the process but are recorded, so that the
//! batch can stop its children first; the handlers found are restored on destruction.
class InterruptWatch {
 public:
  InterruptWatch();
  ~InterruptWatch();
  InterruptWatch(const InterruptWatch&) = delete;
  InterruptWatch& operator=(const InterruptWatch&) = delete;

  //! The signal received, or 0.
  [[nodiscard]] int received() const;
  //! Restores the handlers found and raises the signal received again, so that the process ends
  //! as that signal would have ended it (its exit status names the signal).
  [[noreturn]] void end_as_interrupted();
};

}  // namespace harmonia::cli
