// Writing files: nothing lost, nothing half-written (io/atomic_file.h). A symbolic link at the
// target is written through and stays a link, an existing file keeps its permission bits, a full
// disk (/dev/full) fails with the system's reason and changes nothing, an unwritable output is
// found before any work, and a writer killed while it writes (SIGKILL, SIGINT, SIGTERM) leaves the
// old file whole and no temporary file behind (where the new file must be named, on SIGINT and
// SIGTERM through remove_unfinished_outputs_on_signals).
#include <sched.h>
#include <signal.h>
#include <sys/mount.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "harmonia/io.h"
#include "harmonia/procedural.h"
#include "harmonia/types.h"
#include "io/atomic_file.h"
#include "support/test_support.h"

namespace harmonia {
namespace {

namespace fs = std::filesystem;

class AtomicWrites : public ::testing::Test {
 protected:
  fs::path file(const std::string& name) const { return scratch_.path() / name; }
  std::string read_text(const fs::path& path) const {
    std::ifstream in(path, std::ios::binary);
    std::stringstream text;
    text << in.rdbuf();
    return text.str();
  }
  void write_text(const fs::path& path, const std::string& text) const {
    std::ofstream(path, std::ios::binary) << text;
  }
  std::vector<std::string> names() const {
    std::vector<std::string> found;
    for (const auto& entry : fs::directory_iterator(scratch_.path()))
      found.push_back(entry.path().filename().string());
    std::sort(found.begin(), found.end());
    return found;
  }
  static unsigned mode_of(const fs::path& path) {
    struct stat status {};
    EXPECT_EQ(::stat(path.c_str(), &status), 0) << path;
    return status.st_mode & 07777u;
  }
  testing::ScratchFolder scratch_{"atomic"};
};

Status status_of(const std::function<void()>& work, std::string* message = nullptr) {
  try {
    work();
  } catch (const Error& error) {
    if (message != nullptr) *message = error.what();
    return error.status();
  }
  return Status::ok;
}

TEST_F(AtomicWrites, ALinkAtTheTargetIsWrittenThroughAndStaysALink) {
  const Mesh mesh = hemisphere(2);
  write_text(file("real.obj"), "old\n");
  fs::create_symlink("real.obj", file("link.obj"));  // Relative, as users make them.
  write_mesh(file("link.obj"), mesh);
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(file("link.obj"))));
  EXPECT_EQ(fs::read_symlink(file("link.obj")), fs::path("real.obj"));
  EXPECT_EQ(read_obj(file("real.obj")).faces, mesh.faces);
  // A link that leads nowhere yet: the file it names is created.
  fs::create_symlink("later.obj", file("dangling.obj"));
  write_mesh(file("dangling.obj"), mesh);
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(file("dangling.obj"))));
  EXPECT_EQ(read_obj(file("later.obj")).faces, mesh.faces);
  EXPECT_EQ(names(), (std::vector<std::string>{"dangling.obj", "later.obj", "link.obj", "real.obj"}));
}

TEST_F(AtomicWrites, AnExistingFileKeepsItsModeAndANewOneGetsTheUmasks) {
  const Mesh mesh = hemisphere(2);
  write_text(file("private.obj"), "old\n");
  fs::permissions(file("private.obj"), fs::perms::owner_read | fs::perms::owner_write);
  write_mesh(file("private.obj"), mesh);
  EXPECT_EQ(mode_of(file("private.obj")), 0600u);
  write_text(file("shared.obj"), "old\n");
  fs::permissions(file("shared.obj"), fs::perms::owner_all | fs::perms::group_read);
  write_mesh(file("shared.obj"), mesh);
  EXPECT_EQ(mode_of(file("shared.obj")), 0740u);
  const mode_t umask_now = ::umask(022);  // Read the process's umask (and put it back).
  ::umask(umask_now);
  write_mesh(file("new.obj"), mesh);
  EXPECT_EQ(mode_of(file("new.obj")), 0666u & ~static_cast<unsigned>(umask_now));
}

TEST_F(AtomicWrites, AFullDiskFailsWithItsReasonAndChangesNothing) {
  struct stat device {};
  if (::stat("/dev/full", &device) != 0 || !S_ISCHR(device.st_mode))
    GTEST_SKIP() << "no /dev/full on this system";
  // /dev/full takes no byte: every write fails with ENOSPC, as on a full disk.
  fs::create_symlink("/dev/full", file("full.obj"));
  std::string message;
  EXPECT_EQ(status_of([&] { write_mesh(file("full.obj"), hemisphere(2)); }, &message),
            Status::io_error);
  EXPECT_NE(message.find("full.obj: cannot write"), std::string::npos) << message;
  EXPECT_NE(message.find("No space left on device"), std::string::npos) << message;
  ASSERT_EQ(::stat("/dev/full", &device), 0);
  EXPECT_TRUE(S_ISCHR(device.st_mode));
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(file("full.obj"))));
  EXPECT_EQ(names(), std::vector<std::string>{"full.obj"});
}

TEST_F(AtomicWrites, UnwritableOutputsAreFoundBeforeAnyWork) {
  std::string message;
  EXPECT_EQ(status_of([&] { check_writable(file("no-folder") / "out.obj"); }, &message),
            Status::io_error);
  EXPECT_NE(message.find("no-folder/out.obj: cannot write: no folder"), std::string::npos)
      << message;
  fs::create_directory(file("taken.obj"));
  EXPECT_EQ(status_of([&] { check_writable(file("taken.obj")); }, &message), Status::io_error);
  EXPECT_NE(message.find("taken.obj: cannot write: it is a directory"), std::string::npos)
      << message;
  write_text(file("plain"), "a file, not a folder\n");
  EXPECT_EQ(status_of([&] { check_writable(file("plain") / "out.obj"); }, &message),
            Status::io_error);
  EXPECT_EQ(status_of([&] { check_writable(file("fine.obj")); }), Status::ok);
  EXPECT_FALSE(fs::exists(file("fine.obj")));  // Checking creates nothing.
  if (::geteuid() != 0) {  // root may write anywhere: the permission case needs another user.
    fs::create_directory(file("locked"));
    fs::permissions(file("locked"), fs::perms::owner_read | fs::perms::owner_exec);
    EXPECT_EQ(status_of([&] { check_writable(file("locked") / "out.obj"); }), Status::io_error);
    fs::permissions(file("locked"), fs::perms::owner_all);
  }
}

// A child process rewrites `out` with 64 MB (the size of a large mesh's OBJ) over and over until
// the signal ends it: nearly all of its time goes to writing and flushing the file, so the signal
// lands in the middle of a write. The parent then finds `out` whole (one of the complete versions)
// and nothing else in the folder.
// Hides /proc from this process under an empty tmpfs, in a mount namespace of its own; false where
// that is not allowed (it needs root).
bool hide_proc() {
  return ::unshare(CLONE_NEWNS) == 0 &&
         ::mount(nullptr, "/", nullptr, MS_REC | MS_PRIVATE, nullptr) == 0 &&
         ::mount("none", "/proc", "tmpfs", 0, nullptr) == 0;
}

constexpr int cannot_hide_proc = 77;  // A child's exit status: the test is skipped.

// How the writer of expect_a_killed_writer_leaves_no_trace runs.
enum class Writer {
  unnamed,               // O_TMPFILE: nothing to remove on any signal.
  named_with_handlers,   // No /proc, so named new files, and remove_unfinished_outputs_on_signals.
};

void expect_a_killed_writer_leaves_no_trace(const fs::path& folder, int signal_number,
                                            Writer writer = Writer::unnamed) {
  const std::string contents(64u << 20, 'x');
  const fs::path out = folder / "out.obj";
  detail::write_file_atomically(out, contents);
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (writer == Writer::named_with_handlers) {
      if (!hide_proc()) ::_exit(cannot_hide_proc);
      remove_unfinished_outputs_on_signals();
    }
    for (;;) detail::write_file_atomically(out, contents);  // Ended by the signal.
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));
  ASSERT_EQ(::kill(child, signal_number), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  if (WIFEXITED(status) && WEXITSTATUS(status) == cannot_hide_proc) {
    GTEST_SKIP() << "no mount namespace here (needs root)";
  }
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signal_number) << status;
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(folder))
    left.push_back(entry.path().filename().string());
  EXPECT_EQ(left, std::vector<std::string>{"out.obj"}) << "signal " << signal_number;
  EXPECT_EQ(fs::file_size(out), contents.size());
}

// Without /proc (some containers) the unnamed new file could not be given its name: every write
// failed with "cannot name the new file". A child process in a mount namespace of its own hides
// /proc under an empty tmpfs and writes; skipped where namespaces are not allowed.
TEST_F(AtomicWrites, WritesWorkWithoutProc) {
  const fs::path target = file("no-proc.txt");
  write_text(target, "old");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    if (!hide_proc()) ::_exit(cannot_hide_proc);
    try {
      detail::write_file_atomically(target, "new");
    } catch (...) {
      ::_exit(1);
    }
    ::_exit(0);
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFEXITED(status));
  if (WEXITSTATUS(status) == cannot_hide_proc) GTEST_SKIP() << "no mount namespace here";
  EXPECT_EQ(WEXITSTATUS(status), 0) << "the write failed without /proc";
  EXPECT_EQ(read_text(target), "new");
  EXPECT_EQ(names(), std::vector<std::string>{"no-proc.txt"});
}

TEST_F(AtomicWrites, AWriterKilledWhileItWritesLeavesTheFileWholeAndNoTemporary) {
  for (const int signal_number : {SIGKILL, SIGINT, SIGTERM}) {
    const fs::path folder = file("signal-" + std::to_string(signal_number));
    fs::create_directory(folder);
    expect_a_killed_writer_leaves_no_trace(folder, signal_number);
  }
}

// Where the new file must be named beside the target (here: no /proc), a program that installed
// remove_unfinished_outputs_on_signals leaves no temporary file on SIGINT or SIGTERM either, and
// still dies of the signal. (Without the handlers, 'out.obj.tmp-PID-N' stayed behind.)
TEST_F(AtomicWrites, AnInterruptedProgramLeavesNoNamedTemporary) {
  for (const int signal_number : {SIGINT, SIGTERM}) {
    const fs::path folder = file("named-" + std::to_string(signal_number));
    fs::create_directory(folder);
    expect_a_killed_writer_leaves_no_trace(folder, signal_number, Writer::named_with_handlers);
  }
}

}  // namespace
}  // namespace harmonia
