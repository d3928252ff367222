// Replacing a file atomically, as a careful Unix tool does (docs/robustness.md, "The output
// file"): the new contents go to a temporary file in the target's own folder, which is renamed
// over the target only once complete.
//
// - A symbolic link is followed to the file it names, which is replaced (the link stays).
// - An existing file's mode and, where the process may set them, owner and group carry over.
// - A directory, a dangling link, a special file and a name that cannot be looked up are
//   refused (OutputRefused) before anything is written; so is a read-only file, unless
//   replace_read_only.
// - A hard link is split: the target name gets the new file, other names keep the old one.
// - The temporary is an unnamed O_TMPFILE where the file system has them (nothing is left
//   even after SIGKILL), linked under a short name only for the rename. Elsewhere it is named
//   ".sphray-<hash of the target's name>-<pid>-<n>.tmp" and locked (flock) while in use; a run
//   writing the same target removes such files whose lock is free (their writer is dead).
// - Its descriptor is never 0, 1 or 2, so a closed standard stream is not written into it.
#pragma once

#include <sys/stat.h>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>

namespace sphray::render::detail {

class AtomicOutput {
 public:
  /// Resolves target and creates the temporary. Throws OutputRefused or IoError.
  AtomicOutput(const std::filesystem::path& target, bool replace_read_only);
  ~AtomicOutput();
  AtomicOutput(const AtomicOutput&) = delete;
  AtomicOutput& operator=(const AtomicOutput&) = delete;

  /// Appends bytes to the temporary. Throws IoError.
  void write(const void* data, std::size_t size);
  /// Gives the temporary the target's permissions and renames it over the target. Throws
  /// IoError; the temporary is gone either way.
  void commit();

  /// The file that will be replaced or created (target with its links followed).
  const std::filesystem::path& resolved() const { return resolved_; }
  /// Whether the temporary has no name (O_TMPFILE).
  bool unnamed() const { return temporary_name_.empty(); }

 private:
  void create_temporary();
  bool create_unnamed();
  void create_named();
  void give_name();
  void apply_permissions();
  void discard() noexcept;

  std::filesystem::path target_;    // as given, for messages
  std::filesystem::path resolved_;  // the regular file or new name it stands for
  std::optional<struct stat> existing_;
  int dir_fd_ = -1;
  int fd_ = -1;
  std::string temporary_name_;  // in dir_fd_; empty while unnamed
  bool signal_slot_ = false;
};

/// "-<16 hex digits>-": the part of a temporary's name that says which target it is for.
std::string temporary_tag(const std::string& target_name);

/// Removes the temporaries for target_name in dir_fd whose writer is gone (lock free). Returns
/// how many were removed.
std::size_t remove_stale_temporaries(int dir_fd, const std::string& target_name);

}  // namespace sphray::render::detail
