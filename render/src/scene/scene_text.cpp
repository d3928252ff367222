#include "scene/scene_text.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "sphray/render/scene.hpp"

namespace sphray::render {
namespace {

class FileDescriptor {
 public:
  explicit FileDescriptor(int fd) : fd_(fd) {}
  ~FileDescriptor() {
    if (fd_ >= 0) ::close(fd_);
  }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

 private:
  int fd_;
};

[[noreturn]] void refuse(std::string_view source, const std::string& what) {
  throw SceneError(std::string(source) + ": " + what);
}

[[noreturn]] void refuse_errno(std::string_view source, int error) {
  refuse(source, std::string("cannot read the scene file (") + std::strerror(error) + ")");
}

std::string too_large() {
  return "expected a scene file of at most " + std::to_string(kMaxSceneBytes >> 20) +
         " MiB, got more";
}

// Waits until fd (a FIFO opened without blocking) is readable or hung up, for at most the
// first-byte wait. Returns false on timeout.
bool wait_readable(int fd, std::string_view source) {
  pollfd p{fd, POLLIN, 0};
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(kFifoFirstByteWait);
  for (;;) {
    int ready = ::poll(&p, 1, static_cast<int>(ms.count()));
    if (ready > 0) return true;
    if (ready == 0) return false;
    if (errno != EINTR) refuse_errno(source, errno);
  }
}

// Reads fd to its end, at most kMaxSceneBytes. A FIFO (fifo) is first waited for; once its
// first byte arrived, or it hung up, reads block as usual (a slow writer is not an error).
std::string read_all(int fd, std::string_view source, bool fifo) {
  std::string text;
  char buffer[1 << 16];
  bool waited = !fifo;
  for (;;) {
    if (!waited) {
      if (!wait_readable(fd, source)) {
        refuse(source, "expected a writer on the FIFO, got no data within " +
                           std::to_string(kFifoFirstByteWait.count()) + " s");
      }
      waited = true;
      int flags = ::fcntl(fd, F_GETFL);
      if (flags >= 0) ::fcntl(fd, F_SETFL, flags & ~O_NONBLOCK);
    }
    ssize_t n = ::read(fd, buffer, sizeof buffer);
    if (n < 0) {
      if (errno == EINTR) continue;
      refuse_errno(source, errno);
    }
    if (n == 0) return text;
    if (text.size() + static_cast<std::size_t>(n) > kMaxSceneBytes) refuse(source, too_large());
    text.append(buffer, static_cast<std::size_t>(n));
  }
}

}  // namespace

std::string read_scene_file(const std::filesystem::path& file) {
  const std::string source = file.string();
  // O_NONBLOCK: opening a FIFO for reading would otherwise wait for a writer, forever.
  FileDescriptor fd(::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK));
  if (fd.get() < 0) refuse_errno(source, errno);
  struct stat st {};
  if (::fstat(fd.get(), &st) != 0) refuse_errno(source, errno);
  if (S_ISDIR(st.st_mode)) refuse(source, "expected a scene file, got a directory");
  if (S_ISREG(st.st_mode) && static_cast<std::uintmax_t>(st.st_size) > kMaxSceneBytes)
    refuse(source, too_large());
  const bool fifo = S_ISFIFO(st.st_mode);
  if (!fifo) {  // devices and regular files read as usual
    int flags = ::fcntl(fd.get(), F_GETFL);
    if (flags >= 0) ::fcntl(fd.get(), F_SETFL, flags & ~O_NONBLOCK);
  }
  return read_all(fd.get(), source, fifo);
}

std::string read_scene_stdin() {
  // Standard input is the caller's choice of source: a pipe or terminal is waited for.
  return read_all(STDIN_FILENO, kStandardInputSource, false);
}

}  // namespace sphray::render
