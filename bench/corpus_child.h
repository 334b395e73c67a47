#pragma once
// corpus_benchmark's process isolation: each measurement runs in a forked child, so that its
// peak resident size (VmHWM) is its own and a crash or a runaway solver ends only that row. The
// child sends its result back through a pipe as JSON.

#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstring>
#include <functional>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

namespace harmonia::bench {

using Json = nlohmann::ordered_json;

//! Runs `work` in a forked child and returns what it sent back. A child that crashes, times out
//! or sends nothing readable gives {"status": "crashed", "message": ...}.
inline Json run_in_child(const std::function<Json()>& work, int timeout_seconds) {
  std::cout.flush();
  std::cerr.flush();
  int channel[2];
  if (::pipe(channel) != 0) return Json{{"status", "crashed"}, {"message", "pipe() failed"}};
  const pid_t child = ::fork();
  if (child < 0) {
    ::close(channel[0]);
    ::close(channel[1]);
    return Json{{"status", "crashed"}, {"message", "fork() failed"}};
  }
  if (child == 0) {
    ::close(channel[0]);
    ::alarm(static_cast<unsigned>(timeout_seconds));
    Json result;
    try {
      result = work();
    } catch (const std::exception& error) {
      result = Json{{"status", "exception"}, {"message", error.what()}};
    }
    const std::string text = result.dump();
    std::size_t written = 0;
    while (written < text.size()) {
      const ssize_t step = ::write(channel[1], text.data() + written, text.size() - written);
      if (step < 0 && errno == EINTR) continue;
      if (step <= 0) break;
      written += static_cast<std::size_t>(step);
    }
    ::close(channel[1]);
    ::_exit(0);  // No destructors or atexit handlers of the parent's state in the child.
  }
  ::close(channel[1]);
  std::string text;
  char buffer[65536];
  for (;;) {
    const ssize_t got = ::read(channel[0], buffer, sizeof buffer);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) break;
    text.append(buffer, static_cast<std::size_t>(got));
  }
  ::close(channel[0]);
  int wait_status = 0;
  while (::waitpid(child, &wait_status, 0) < 0 && errno == EINTR) {
  }
  if (WIFSIGNALED(wait_status)) {
    const int signal_number = WTERMSIG(wait_status);
    return Json{{"status", signal_number == SIGALRM ? "timeout" : "crashed"},
                {"message", signal_number == SIGALRM
                                ? "no result within " + std::to_string(timeout_seconds) + " s"
                                : std::string("killed by signal ") + ::strsignal(signal_number)}};
  }
  try {
    return Json::parse(text);
  } catch (const std::exception&) {
    return Json{{"status", "crashed"}, {"message", "the child sent no readable result"}};
  }
}

}  // namespace harmonia::bench
