#pragma once
// Writing a file so that it is either completely replaced or left untouched.
//
// The content goes to a new file in the target's own folder (so that the final rename stays on
// one file system, which makes it atomic on POSIX), and only a fully written, flushed and closed
// file is renamed over the target. Where the file system supports it (ext4, xfs, btrfs, tmpfs) the
// new file is created without a name (O_TMPFILE) and given one only just before the rename: a
// process killed while it writes (SIGKILL included) leaves nothing behind. Elsewhere (or where
// /proc, through which it is named, is missing) it is a named file beside the target, removed on
// every failure the process lives through, and by remove_unfinished_outputs, which a program's
// SIGINT/SIGTERM handler calls (the harmonia program does; the library installs no handler).
//
// What users expect of tools that rewrite files holds too: a symbolic link at the target is
// written through (its target file is replaced, the link stays), an existing file keeps its
// permission bits, and a target that is not a regular file (a device such as /dev/null or
// /dev/full, a pipe) is written directly, since there is no file to replace.

#include <filesystem>
#include <string_view>

namespace harmonia::detail {

//! Writes `contents` to `path` atomically. Throws Error(io_error) naming the file on any failure;
//! an existing `path` is then unchanged and no temporary file is left.
void write_file_atomically(const std::filesystem::path& path, std::string_view contents);

//! Throws Error(io_error) naming the file unless write_file_atomically(path, ...) could create its
//! file now: the folder exists and is a folder that this process may create files in, and `path`
//! is not a folder. Lets a program refuse an unwritable output before it starts the work.
void check_writable(const std::filesystem::path& path);

//! Removes the named new files being written at this moment (harmonia::remove_unfinished_outputs).
void remove_unfinished_outputs() noexcept;

}  // namespace harmonia::detail
