#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <string>
#include <system_error>

#include "harmonia/types.h"

namespace harmonia::detail {
namespace {

namespace fs = std::filesystem;

[[noreturn]] void fail(const fs::path& path, const std::string& what, int error) {
  throw Error(Status::io_error,
              path.string() + ": cannot write: " + what + (error != 0 ? ": " : "") +
                  (error != 0 ? std::strerror(error) : ""));
}

// The file a write to `path` replaces: `path` itself, or the file its symbolic link(s) lead to
// (a dangling link: the path it names, which the write creates).
fs::path resolved_target(const fs::path& path) {
  std::error_code error;
  fs::path target = path;
  for (int hops = 0; hops < 40 && fs::is_symlink(fs::symlink_status(target, error)); ++hops) {
    const fs::path link = fs::read_symlink(target, error);
    if (error) break;
    target = link.is_absolute() ? link : target.parent_path() / link;
  }
  return target;
}

fs::path folder_of(const fs::path& target) {
  return target.has_parent_path() ? target.parent_path() : fs::path(".");
}

// A name beside the target that no other writer (thread or process) uses at the same time.
fs::path temporary_name(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  fs::path temporary = target;
  temporary += ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter++);
  return temporary;
}

// The named new files being written now, for remove_unfinished_outputs, which a signal handler
// calls: it may only read memory that stays valid and call unlink (async-signal-safe). So the
// names live in fixed slots, each claimed by a writer (free -> filling), filled, published
// (-> named) and given back (-> free) before its file is renamed or removed.
constexpr std::size_t unfinished_slot_count = 64;
constexpr std::size_t unfinished_name_bytes = 4096;  // PATH_MAX
enum SlotState : int { free_slot, filling_slot, named_slot };
struct UnfinishedSlot {
  std::atomic<int> state{free_slot};
  char name[unfinished_name_bytes];
};
UnfinishedSlot unfinished_slots[unfinished_slot_count];

// Records `name`; the slot's index, or -1 when every slot is taken or the name is too long (the
// file is then still removed on every failure the process lives through, only not on a signal).
int record_unfinished(const fs::path& name) {
  const std::string& text = name.native();
  if (text.size() >= unfinished_name_bytes) return -1;
  for (std::size_t k = 0; k < unfinished_slot_count; ++k) {
    int expected = free_slot;
    if (!unfinished_slots[k].state.compare_exchange_strong(expected, filling_slot)) continue;
    std::memcpy(unfinished_slots[k].name, text.c_str(), text.size() + 1);
    unfinished_slots[k].state.store(named_slot);
    return static_cast<int>(k);
  }
  return -1;
}

void forget_unfinished(int slot) {
  if (slot >= 0) unfinished_slots[static_cast<std::size_t>(slot)].state.store(free_slot);
}

// Writes every byte to `descriptor`; the errno of the failure, or 0.
int write_all(int descriptor, std::string_view contents) {
  while (!contents.empty()) {
    const ssize_t written = ::write(descriptor, contents.data(), contents.size());
    if (written < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    contents.remove_prefix(static_cast<std::size_t>(written));
  }
  return 0;
}

// A device, a pipe or another non-regular file at the target is written as it is.
void write_in_place(const fs::path& path, const fs::path& target, std::string_view contents) {
  const int descriptor = ::open(target.c_str(), O_WRONLY | O_CLOEXEC | O_NOCTTY);
  if (descriptor < 0) fail(path, "cannot open " + target.string(), errno);
  const int error = write_all(descriptor, contents);
  const bool closed = ::close(descriptor) == 0;
  if (error != 0) fail(path, "writing failed", error);
  if (!closed) fail(path, "writing failed", errno);
}

// The new file being written, with or without a name, removed unless it was renamed into place.
class NewFile {
 public:
  NewFile(const fs::path& path, const fs::path& target) : path_(path), target_(target) {
    // Unnamed first (O_TMPFILE): nothing is left if the process dies before the rename. It is
    // named through /proc/self/fd (linkat with AT_EMPTY_PATH needs a privilege), so without /proc
    // (some containers) the file is named from the start.
    if (::access("/proc/self/fd", X_OK) == 0) {
      descriptor_ = ::open(folder_of(target).c_str(), O_TMPFILE | O_WRONLY | O_CLOEXEC, 0666);
      if (descriptor_ >= 0) return;
      const int unnamed_error = errno;
      // File systems without O_TMPFILE answer EOPNOTSUPP, EISDIR or EINVAL: a named file then.
      if (unnamed_error != EOPNOTSUPP && unnamed_error != EISDIR && unnamed_error != EINVAL)
        fail(path_, "cannot create a file in " + folder_of(target).string(), unnamed_error);
    }
    name_ = temporary_name(target);
    // Recorded before it exists, so that a signal at any later moment finds it.
    slot_ = record_unfinished(name_);
    descriptor_ = ::open(name_.c_str(), O_CREAT | O_EXCL | O_WRONLY | O_CLOEXEC, 0666);
    if (descriptor_ < 0) {
      const int error = errno;
      forget_unfinished(slot_);
      name_.clear();
      fail(path_, "cannot create " + temporary_name(target).string(), error);
    }
  }
  ~NewFile() {
    if (descriptor_ >= 0) ::close(descriptor_);
    if (!name_.empty()) ::unlink(name_.c_str());
    forget_unfinished(slot_);
  }
  NewFile(const NewFile&) = delete;
  NewFile& operator=(const NewFile&) = delete;

  void write(std::string_view contents, const struct stat* existing) {
    // An existing file keeps its permission bits (new files get 0666 less the umask).
    if (existing != nullptr && ::fchmod(descriptor_, existing->st_mode & 07777) != 0)
      fail(path_, "cannot give the new file the mode of " + target_.string(), errno);
    if (const int error = write_all(descriptor_, contents); error != 0)
      fail(path_, "writing failed", error);
    // On disk before it replaces the old file: a crash after the rename finds the new contents.
    if (::fsync(descriptor_) != 0) fail(path_, "writing failed", errno);
  }

  void replace_target() {
    if (name_.empty()) {
      // The unnamed file gets a name only now, with its data complete and on disk, and is renamed
      // over the target by the very next call: Linux cannot link an unnamed file over an existing
      // one, so these two adjacent calls are the only moment at which a SIGKILL leaves a file.
      const fs::path name = temporary_name(target_);
      const std::string descriptor_path = "/proc/self/fd/" + std::to_string(descriptor_);
      slot_ = record_unfinished(name);  // Between the link and the rename, a signal removes it.
      if (::linkat(AT_FDCWD, descriptor_path.c_str(), AT_FDCWD, name.c_str(),
                   AT_SYMLINK_FOLLOW) != 0)
        fail(path_, "cannot name the new file " + name.string(), errno);
      if (::rename(name.c_str(), target_.c_str()) != 0) {
        const int error = errno;
        name_ = name;  // Removed by the destructor.
        fail(path_, "renaming " + name.string() + " into place failed", error);
      }
    } else if (::rename(name_.c_str(), target_.c_str()) != 0) {
      fail(path_, "renaming " + name_.string() + " into place failed", errno);
    }
    forget_unfinished(slot_);
    slot_ = -1;
    name_.clear();
    // Closed after the rename, so that nothing comes between the link and the rename. The data
    // was flushed to disk before either (write(): fsync), so closing has nothing left to lose, and
    // the new file is in place: its result is not an error of the write.
    ::close(descriptor_);
    descriptor_ = -1;
  }

 private:
  fs::path path_, target_, name_;
  int descriptor_ = -1;
  int slot_ = -1;  // In unfinished_slots while the named new file is being written.
};

}  // namespace

void check_writable(const fs::path& path) {
  const fs::path target = resolved_target(path);
  struct stat existing {};
  if (::stat(target.c_str(), &existing) == 0) {
    if (S_ISDIR(existing.st_mode)) fail(path, "it is a directory", 0);
    if (!S_ISREG(existing.st_mode)) {
      if (::access(target.c_str(), W_OK) != 0) fail(path, "cannot open " + target.string(), errno);
      return;
    }
  }
  const fs::path folder = folder_of(target);
  struct stat folder_status {};
  if (::stat(folder.c_str(), &folder_status) != 0)
    fail(path, "no folder " + folder.string(), errno);
  if (!S_ISDIR(folder_status.st_mode)) fail(path, folder.string() + " is not a folder", 0);
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    fail(path, "cannot create a file in " + folder.string(), errno);
}

void write_file_atomically(const fs::path& path, std::string_view contents) {
  const fs::path target = resolved_target(path);
  struct stat existing {};
  const bool exists = ::stat(target.c_str(), &existing) == 0;
  if (exists && S_ISDIR(existing.st_mode)) fail(path, "it is a directory", 0);
  if (exists && !S_ISREG(existing.st_mode)) return write_in_place(path, target, contents);
  NewFile file(path, target);
  file.write(contents, exists ? &existing : nullptr);
  file.replace_target();
}

void remove_unfinished_outputs() noexcept {
  for (UnfinishedSlot& slot : unfinished_slots) {
    if (slot.state.load() == named_slot) ::unlink(slot.name);
  }
}

}  // namespace harmonia::detail
