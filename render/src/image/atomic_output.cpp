#include "image/atomic_output.hpp"

#include <dirent.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "image/cleanup_signals.hpp"
#include "sphray/render/image_file.hpp"

namespace sphray::render::detail {
namespace {

namespace fs = std::filesystem;

// As many links as Linux follows in one lookup (MAXSYMLINKS).
constexpr int kMaxLinks = 40;

std::string quoted_error(int error) {
  return std::string("(") + std::strerror(error) + ")";
}

[[noreturn]] void refuse(const fs::path& target, const std::string& what) {
  throw OutputRefused(target.string() + ": " + what);
}

IoError io_error(const fs::path& target, const std::string& what, int error) {
  return IoError(target.string() + ": " + what + " " + quoted_error(error));
}

// Moves fd above the standard streams: with stderr closed, a new file would be descriptor 2,
// and every warning printed to stderr would land in the image.
int above_standard_streams(int fd) {
  if (fd < 0 || fd > STDERR_FILENO) return fd;
  int moved = ::fcntl(fd, F_DUPFD_CLOEXEC, STDERR_FILENO + 1);
  int error = errno;
  ::close(fd);
  errno = error;
  return moved;
}

// The process's umask, which a new file's mode is subject to. Read from /proc where it is
// shown; otherwise set and restored at once.
mode_t current_umask() {
  if (FILE* status = std::fopen("/proc/self/status", "re")) {
    char line[256];
    unsigned mask = 0;
    bool found = false;
    while (!found && std::fgets(line, sizeof line, status) != nullptr)
      found = std::sscanf(line, "Umask: %o", &mask) == 1;
    std::fclose(status);
    if (found) return static_cast<mode_t>(mask);
  }
  mode_t mask = ::umask(022);
  ::umask(mask);
  return mask;
}

// Follows path's symbolic links to the file they end at (or the new name they point to).
fs::path follow_links(const fs::path& target, std::optional<struct stat>& existing) {
  fs::path path = target;
  for (int links = 0;; ++links) {
    struct stat st {};
    if (::lstat(path.c_str(), &st) != 0) {
      int error = errno;
      if (error != ENOENT) refuse(target, "cannot use it as the output " + quoted_error(error));
      if (links > 0) refuse(target, "expected an output file, got a dangling symbolic link");
      return path;  // a new file; a missing folder is reported when the temporary is created
    }
    if (!S_ISLNK(st.st_mode)) {
      if (S_ISDIR(st.st_mode)) refuse(target, "expected an output file, got a directory");
      if (!S_ISREG(st.st_mode))
        refuse(target, "expected a regular file or a new name as the output");
      existing = st;
      return path;
    }
    if (links == kMaxLinks) refuse(target, "cannot use it as the output " + quoted_error(ELOOP));
    std::string link(static_cast<std::size_t>(st.st_size > 0 ? st.st_size : 255) + 1, '\0');
    ssize_t n = ::readlink(path.c_str(), link.data(), link.size());
    if (n < 0) refuse(target, "cannot use it as the output " + quoted_error(errno));
    link.resize(static_cast<std::size_t>(n));
    fs::path next(link);
    path = next.is_absolute() ? next : path.parent_path() / next;
  }
}

// Whether a file counts as read-only: no write permission bit at all (so even root, who may
// write anything, is told), or none for this process.
bool read_only(const fs::path& path, const struct stat& st) {
  return (st.st_mode & 0222) == 0 || ::faccessat(AT_FDCWD, path.c_str(), W_OK, AT_EACCESS) != 0;
}

bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    ssize_t written = ::write(fd, p, size);
    if (written < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    p += written;
    size -= static_cast<std::size_t>(written);
  }
  return true;
}

// FNV-1a: a fixed-length tag for a name of any length.
std::uint64_t fnv1a(const std::string& text) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (unsigned char c : text) {
    h ^= c;
    h *= 0x100000001b3ull;
  }
  return h;
}

constexpr std::string_view kPrefix = ".sphray";
constexpr std::string_view kSuffix = ".tmp";

// O_TMPFILE can be turned off to exercise the named temporaries on file systems that have it.
bool unnamed_allowed() {
  const char* choice = std::getenv("SPHRAY_TMPFILE");
  return choice == nullptr || std::string_view(choice) != "named";
}

}  // namespace

std::string temporary_tag(const std::string& target_name) {
  char tag[20];
  std::snprintf(tag, sizeof tag, "-%016llx-", static_cast<unsigned long long>(fnv1a(target_name)));
  return tag;
}

std::size_t remove_stale_temporaries(int dir_fd, const std::string& target_name) {
  int list_fd = ::openat(dir_fd, ".", O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (list_fd < 0) return 0;
  DIR* dir = ::fdopendir(list_fd);
  if (dir == nullptr) {
    ::close(list_fd);
    return 0;
  }
  const std::string start = std::string(kPrefix) + temporary_tag(target_name);
  std::size_t removed = 0;
  while (const dirent* entry = ::readdir(dir)) {
    std::string_view name(entry->d_name);
    if (!name.starts_with(start) || !name.ends_with(kSuffix)) continue;
    int fd = ::openat(dir_fd, entry->d_name, O_RDONLY | O_CLOEXEC | O_NOFOLLOW | O_NONBLOCK);
    if (fd < 0) continue;
    // A live writer holds an exclusive lock on its temporary until it is renamed; a free lock
    // means its writer died (the lock goes with the last descriptor, even on SIGKILL).
    struct stat st {};
    if (::flock(fd, LOCK_EX | LOCK_NB) == 0 && ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode) &&
        ::unlinkat(dir_fd, entry->d_name, 0) == 0) {
      ++removed;
    }
    ::close(fd);
  }
  ::closedir(dir);
  return removed;
}

AtomicOutput::AtomicOutput(const fs::path& target, bool replace_read_only) : target_(target) {
  resolved_ = follow_links(target, existing_);
  if (existing_ && !replace_read_only && read_only(resolved_, *existing_))
    refuse(target, "the output file is read-only (use --force to replace it)");
  fs::path folder = resolved_.parent_path();
  if (folder.empty()) folder = ".";
  dir_fd_ = above_standard_streams(::open(folder.c_str(), O_PATH | O_DIRECTORY | O_CLOEXEC));
  if (dir_fd_ < 0) throw io_error(target_, "cannot create the output file", errno);
  try {
    create_temporary();
  } catch (...) {
    ::close(dir_fd_);
    throw;
  }
  remove_stale_temporaries(dir_fd_, resolved_.filename().string());
}

AtomicOutput::~AtomicOutput() {
  discard();
  if (dir_fd_ >= 0) ::close(dir_fd_);
}

void AtomicOutput::create_temporary() {
  if (unnamed_allowed() && create_unnamed()) return;
  create_named();
}

bool AtomicOutput::create_unnamed() {
  // Mode 0600 until commit() gives the final one: the image is nobody else's business before.
  fd_ = above_standard_streams(::openat(dir_fd_, ".", O_TMPFILE | O_WRONLY | O_CLOEXEC, 0600));
  if (fd_ >= 0) {
    ::flock(fd_, LOCK_EX);  // held when it gets a name in commit()
    return true;
  }
  // Not supported by this kernel or file system: use a named temporary. Any other error (no
  // such folder, no permission) is the same for both.
  if (errno == EOPNOTSUPP || errno == EISDIR || errno == EINVAL) return false;
  throw io_error(target_, "cannot create the output file", errno);
}

void AtomicOutput::create_named() {
  static std::atomic<unsigned> counter{0};
  const std::string tag = temporary_tag(resolved_.filename().string());
  for (;;) {
    std::string name = std::string(kPrefix) + tag + std::to_string(::getpid()) + "-" +
                       std::to_string(counter++) + std::string(kSuffix);
    // Armed before the file exists: a signal between creating and arming would leave it. A
    // signal before the open unlinks a name that is not there (or, if the open is about to
    // fail with EEXIST, a dead process's temporary with this pid, which is stale anyway).
    const bool armed = arm_signal_cleanup(dir_fd_, name.c_str());
    int fd = above_standard_streams(
        ::openat(dir_fd_, name.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600));
    if (fd < 0) {
      const int error = errno;
      if (armed) disarm_signal_cleanup();
      if (error == EEXIST) continue;
      throw io_error(target_, "cannot create the output file", error);
    }
    struct stat st {};
    // Another run's cleanup may have taken the lock and removed the name between the open and
    // the flock; then the file has no name left, and a new one is made.
    if (::flock(fd, LOCK_EX) != 0 || ::fstat(fd, &st) != 0 || st.st_nlink == 0) {
      ::close(fd);
      if (armed) disarm_signal_cleanup();
      continue;
    }
    fd_ = fd;
    temporary_name_ = name;
    signal_slot_ = armed;
    return;
  }
}

void AtomicOutput::write(const void* data, std::size_t size) {
  if (!write_all(fd_, data, size)) throw io_error(target_, "cannot write the output file", errno);
}

// The existing file's owner, group and mode; for a new file, 0666 less the umask, as if it
// had been created directly. A set-id bit is kept only with the original owner and group.
void AtomicOutput::apply_permissions() {
  mode_t mode = static_cast<mode_t>(0666) & ~current_umask();
  if (existing_) {
    mode = existing_->st_mode & 07777;
    struct stat mine {};
    if (::fstat(fd_, &mine) == 0 &&
        (mine.st_uid != existing_->st_uid || mine.st_gid != existing_->st_gid)) {
      if (::fchown(fd_, existing_->st_uid, existing_->st_gid) != 0) {
        (void)::fchown(fd_, static_cast<uid_t>(-1), existing_->st_gid);  // the group, if ours
        mode &= ~static_cast<mode_t>(S_ISUID | S_ISGID);
      }
    }
  }
  if (::fchmod(fd_, mode) != 0) throw io_error(target_, "cannot set the output's mode", errno);
}

// An unnamed temporary gets a name beside the target for the rename (linkat cannot replace).
void AtomicOutput::give_name() {
  static std::atomic<unsigned> counter{0};
  const std::string tag = temporary_tag(resolved_.filename().string());
  char proc_path[64];
  std::snprintf(proc_path, sizeof proc_path, "/proc/self/fd/%d", fd_);
  for (;;) {
    std::string name = std::string(kPrefix) + tag + std::to_string(::getpid()) + "-l" +
                       std::to_string(counter++) + std::string(kSuffix);
    signal_slot_ = arm_signal_cleanup(dir_fd_, name.c_str());
    int linked = ::linkat(AT_FDCWD, proc_path, dir_fd_, name.c_str(), AT_SYMLINK_FOLLOW);
    if (linked != 0 && errno == ENOENT) {  // no /proc: the privileged way, if allowed
      linked = ::linkat(fd_, "", dir_fd_, name.c_str(), AT_EMPTY_PATH);
    }
    if (linked == 0) {
      temporary_name_ = name;
      return;
    }
    int error = errno;
    if (signal_slot_) disarm_signal_cleanup();
    signal_slot_ = false;
    if (error != EEXIST) throw io_error(target_, "cannot write the output file", error);
  }
}

void AtomicOutput::commit() {
  try {
    // Some file systems (NFS) report a failed write only when the data reaches the server;
    // fsync finds it before the old file is replaced, and the lock is still held.
    if (::fsync(fd_) != 0 && errno != EINVAL)
      throw io_error(target_, "cannot write the output file", errno);
    apply_permissions();
    if (temporary_name_.empty()) give_name();
  } catch (...) {
    discard();
    throw;
  }
  if (::renameat(dir_fd_, temporary_name_.c_str(), dir_fd_, resolved_.filename().c_str()) != 0) {
    int error = errno;
    discard();
    throw io_error(target_, "cannot replace the output file", error);
  }
  temporary_name_.clear();  // it is the target now
  if (signal_slot_) disarm_signal_cleanup();
  signal_slot_ = false;
  ::close(fd_);  // releases the lock; fsync already reported any write error
  fd_ = -1;
}

void AtomicOutput::discard() noexcept {
  if (!temporary_name_.empty()) ::unlinkat(dir_fd_, temporary_name_.c_str(), 0);
  temporary_name_.clear();
  if (signal_slot_) disarm_signal_cleanup();
  signal_slot_ = false;
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

}  // namespace sphray::render::detail
