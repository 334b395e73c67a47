#include "cli/batch_child.h"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <iostream>
#include <system_error>

extern char** environ;

namespace harmonia::cli {

namespace {

// How much of a pipe one read takes: the size of a Linux pipe's buffer.
constexpr std::size_t kReadChunkBytes = 65536;

// A NULL-terminated array of C strings pointing into `strings` (which must outlive it), as
// execve takes its argv and envp.
std::vector<char*> c_string_array(std::vector<std::string>& strings) {
  std::vector<char*> array;
  array.reserve(strings.size() + 1);
  for (std::string& text : strings) array.push_back(text.data());
  array.push_back(nullptr);
  return array;
}

// The parent's environment with every `NAME=value` of `overrides` in place of NAME's own entry.
std::vector<std::string> child_environment(const std::vector<std::string>& overrides) {
  const auto name_of = [](const std::string& entry) { return entry.substr(0, entry.find('=')); };
  std::vector<std::string> environment;
  for (char** entry = environ; *entry != nullptr; ++entry) {
    const std::string text(*entry);
    bool overridden = false;
    for (const std::string& override_entry : overrides)
      overridden = overridden || name_of(override_entry) == name_of(text);
    if (!overridden) environment.push_back(text);
  }
  environment.insert(environment.end(), overrides.begin(), overrides.end());
  return environment;
}

// A pipe whose two ends are closed in any program this one executes (the child's copies, moved
// to its standard output and error, are not), so that one child does not hold another's pipe
// open and delay the end of file its parent waits for.
void make_pipe(int (&ends)[2]) {
  if (::pipe2(ends, O_CLOEXEC) != 0)
    throw std::system_error(errno, std::generic_category(), "pipe");
}

void close_pipe(int (&ends)[2]) {
  ::close(ends[0]);
  ::close(ends[1]);
}

// In the forked child: only async-signal-safe calls until execve (the parent may have threads,
// e.g. OpenBLAS's, whose locks the child inherits in whatever state they were).
[[noreturn]] void become_program(const char* program, int output, int error, char** argv,
                                 char** envp, pid_t parent) {
  // The child ends with its parent (a batch killed outright, or the worker of another scheduler
  // that ran `batch --task`): SIGTERM, whose handler removes its unfinished output. A parent that
  // was gone before this line leaves the child nothing to report to.
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) ::_exit(kChildCouldNotStart);
  ::dup2(output, STDOUT_FILENO);
  ::dup2(error, STDERR_FILENO);
  ::execve(program, argv, envp);
  static const char kMessage[] = "harmonia: batch: cannot execute the program for this input\n";
  (void)!::write(STDERR_FILENO, kMessage, sizeof kMessage - 1);
  ::_exit(kChildCouldNotStart);
}

}  // namespace

std::string signal_name(int signal_number) {
#ifdef __GLIBC__
  if (const char* abbreviation = ::sigabbrev_np(signal_number))
    return "SIG" + std::string(abbreviation);
#endif
  return "signal " + std::to_string(signal_number);
}

std::string signal_description(int signal_number) {
  return signal_name(signal_number) + " (" + ::strsignal(signal_number) + ")";
}

ChildPool::ChildPool(std::string program) : program_(std::move(program)) {}

ChildPool::~ChildPool() { terminate_all(); }

void ChildPool::start(int tag, const std::vector<std::string>& arguments,
                      const std::vector<std::string>& environment) {
  // Everything the child needs is made here, before fork: the child only calls execve.
  std::vector<std::string> argument_strings = arguments;
  std::vector<std::string> environment_strings = child_environment(environment);
  std::vector<char*> argv = c_string_array(argument_strings);
  std::vector<char*> envp = c_string_array(environment_strings);
  int output[2];
  int error[2];
  make_pipe(output);
  try {
    make_pipe(error);
  } catch (...) {
    close_pipe(output);
    throw;
  }
  const pid_t parent = ::getpid();
  const pid_t pid = ::fork();
  if (pid < 0) {
    const int fork_error = errno;
    close_pipe(output);
    close_pipe(error);
    throw std::system_error(fork_error, std::generic_category(), "fork");
  }
  if (pid == 0) become_program(program_.c_str(), output[1], error[1], argv.data(), envp.data(), parent);
  ::close(output[1]);
  ::close(error[1]);
  // Non-blocking, so that wait() reads what is there and goes on to the other children.
  for (const int read_end : {output[0], error[0]})
    ::fcntl(read_end, F_SETFL, ::fcntl(read_end, F_GETFL) | O_NONBLOCK);
  Running child;
  child.tag = tag;
  child.pid = pid;
  child.output_pipe = output[0];
  child.error_pipe = error[0];
  child.start = std::chrono::steady_clock::now();
  children_.push_back(std::move(child));
}

void ChildPool::read_available(int& pipe, std::string& into) {
  char buffer[kReadChunkBytes];
  while (pipe >= 0) {
    const ssize_t got = ::read(pipe, buffer, sizeof buffer);
    if (got > 0) {
      into.append(buffer, static_cast<std::size_t>(got));
      continue;
    }
    if (got < 0 && errno == EINTR) continue;
    if (got < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    ::close(pipe);  // End of file (the child has ended), or a pipe that cannot be read.
    pipe = -1;
  }
}

FinishedChild ChildPool::reap(Running& child) {
  int status = 0;
  while (::waitpid(child.pid, &status, 0) < 0 && errno == EINTR) {
  }
  FinishedChild finished;
  finished.tag = child.tag;
  finished.seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - child.start).count();
  if (WIFSIGNALED(status)) finished.signal = WTERMSIG(status);
  if (WIFEXITED(status)) finished.exit_code = WEXITSTATUS(status);
  finished.standard_output = std::move(child.standard_output);
  finished.standard_error = std::move(child.standard_error);
  return finished;
}

std::vector<FinishedChild> ChildPool::wait(std::chrono::milliseconds timeout) {
  std::vector<pollfd> watched;
  for (const Running& child : children_)
    for (const int pipe : {child.output_pipe, child.error_pipe})
      if (pipe >= 0) watched.push_back({pipe, POLLIN, 0});
  // EINTR (a signal) returns at once with nothing ended: the caller looks at what arrived.
  if (::poll(watched.data(), watched.size(), static_cast<int>(timeout.count())) < 0) return {};
  std::vector<FinishedChild> finished;
  for (auto child = children_.begin(); child != children_.end();) {
    read_available(child->output_pipe, child->standard_output);
    read_available(child->error_pipe, child->standard_error);
    // Both pipes at their end: the child has ended (or is ending), so waitpid returns soon.
    if (child->output_pipe < 0 && child->error_pipe < 0) {
      finished.push_back(reap(*child));
      child = children_.erase(child);
    } else {
      ++child;
    }
  }
  return finished;
}

void ChildPool::terminate_all() {
  for (const Running& child : children_) ::kill(child.pid, SIGTERM);
  for (Running& child : children_) {
    for (int* pipe : {&child.output_pipe, &child.error_pipe})
      if (*pipe >= 0) ::close(*pipe);
    int status = 0;
    while (::waitpid(child.pid, &status, 0) < 0 && errno == EINTR) {
    }
  }
  children_.clear();
}

// ------------------------------------------------------------------------------ InterruptWatch

namespace {

volatile sig_atomic_t received_signal = 0;

extern "C" void record_signal(int signal_number) { received_signal = signal_number; }

constexpr int kWatchedSignals[] = {SIGINT, SIGTERM};
struct sigaction handlers_found[std::size(kWatchedSignals)];

}  // namespace

InterruptWatch::InterruptWatch() {
  received_signal = 0;
  struct sigaction action {};
  action.sa_handler = record_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;  // No SA_RESTART: a wait in poll() returns at once to look at the signal.
  for (std::size_t i = 0; i < std::size(kWatchedSignals); ++i)
    ::sigaction(kWatchedSignals[i], &action, &handlers_found[i]);
}

InterruptWatch::~InterruptWatch() {
  for (std::size_t i = 0; i < std::size(kWatchedSignals); ++i)
    ::sigaction(kWatchedSignals[i], &handlers_found[i], nullptr);
}

int InterruptWatch::received() const { return received_signal; }

void InterruptWatch::end_as_interrupted() {
  const int signal_number = received_signal;
  for (std::size_t i = 0; i < std::size(kWatchedSignals); ++i)
    ::sigaction(kWatchedSignals[i], &handlers_found[i], nullptr);
  std::cout.flush();
  std::cerr.flush();
  ::raise(signal_number);
  // A handler found that returns (one that does not end the process) leaves the default action.
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
  ::_exit(128 + signal_number);  // The shell's status for "ended by this signal".
}

}  // namespace harmonia::cli
