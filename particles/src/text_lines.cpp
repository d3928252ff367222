// The text readers' shared reading: a line at a time through one fixed buffer, and the helpers
// that keep their messages one line.
#include "text_lines.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <vector>

#include "sphray/particles/particles.hpp"

namespace sphray::particles::detail {
namespace {

// Closes the file when the reading ends, however it ends.
struct Closing {
  int fd;
  ~Closing() {
    if (fd >= 0) ::close(fd);
  }
};

[[noreturn]] void refuse_errno(const std::string& source, int error) {
  throw ParticleError(source + ": cannot read the particle file (" + std::strerror(error) + ")");
}

[[noreturn]] void refuse_long_line(const std::string& source, std::uint64_t line) {
  throw ParticleError(source + ":" + std::to_string(line) + ": expected lines of at most " +
                      std::to_string(kMaxLineBytes) + " bytes");
}

}  // namespace

std::string quoted(std::string_view field) {
  std::string out = "\"";
  for (std::size_t i = 0; i < field.size() && i < 40; ++i) {
    const auto c = static_cast<unsigned char>(field[i]);
    if (c >= 0x20 && c < 0x7f && c != '"' && c != '\\') {
      out += static_cast<char>(c);
    } else {
      constexpr char kHex[] = "0123456789abcdef";
      out += {'\\', 'x', kHex[c >> 4], kHex[c & 15]};
    }
  }
  return out + (field.size() > 40 ? "...\"" : "\"");
}

std::string lower(std::string_view text) {
  std::string out(text);
  std::transform(out.begin(), out.end(), out.begin(),
                 [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c + 32) : c; });
  return out;
}

std::string shortest(float value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
}

std::string_view trim(std::string_view s) {
  const auto blank = [](char c) {
    return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f';
  };
  while (!s.empty() && blank(s.front()))
    s.remove_prefix(1);
  while (!s.empty() && blank(s.back()))
    s.remove_suffix(1);
  return s;
}

std::optional<float> as_number(std::string_view field, bool& out_of_range) {
  out_of_range = false;
  // A leading '+' (printf's %+g) is a sign; from_chars takes only '-'.
  if (field.starts_with('+')) {
    field.remove_prefix(1);
    if (field.starts_with('+') || field.starts_with('-')) return std::nullopt;  // "+-1"
  }
  float value = 0;
  const char* end = field.data() + field.size();
  const auto [stop, error] = std::from_chars(field.data(), end, value);
  out_of_range = error == std::errc::result_out_of_range && stop == end;
  if (error != std::errc{} || stop != end) return std::nullopt;
  return value;
}

void split_lines(std::string_view text, const std::string& source, const LineSink& sink) {
  std::uint64_t line = 0;
  while (!text.empty()) {
    const std::size_t end = text.find('\n');
    ++line;
    if (std::min(end, text.size()) > kMaxLineBytes) refuse_long_line(source, line);
    if (!sink(text.substr(0, end), line)) return;
    text.remove_prefix(std::min(end, text.size() - 1) + 1);
  }
}

void read_lines(const std::filesystem::path& file, const LineSink& sink) {
  const std::string source = file.string();
  // O_NONBLOCK: opening a FIFO would otherwise wait for a writer; only regular files are read.
  Closing fd{::open(file.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK)};
  if (fd.fd < 0) refuse_errno(source, errno);
  struct stat st {};
  if (::fstat(fd.fd, &st) != 0) refuse_errno(source, errno);
  if (S_ISDIR(st.st_mode))
    throw ParticleError(source + ": expected a particle file, got a directory");
  if (!S_ISREG(st.st_mode)) throw ParticleError(source + ": expected a regular file");
  // One buffer: a line that straddles two reads is moved to its front before the next read.
  std::vector<char> buffer(std::size_t{1} << 16);
  std::size_t held = 0;  // bytes of an unfinished line at the front of buffer
  std::uint64_t line = 0;
  for (;;) {
    const ssize_t n = ::read(fd.fd, buffer.data() + held, buffer.size() - held);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) refuse_errno(source, errno);
    const std::size_t filled = held + static_cast<std::size_t>(n);
    std::string_view text(buffer.data(), filled);
    std::size_t end;
    while ((end = text.find('\n')) != std::string_view::npos) {
      ++line;
      if (end > kMaxLineBytes) break;
      if (!sink(text.substr(0, end), line)) return;
      text.remove_prefix(end + 1);
    }
    if (text.size() > kMaxLineBytes || (end != std::string_view::npos))
      refuse_long_line(source, line + (end == std::string_view::npos));
    if (n == 0) {
      if (!text.empty()) sink(text, line + 1);  // the last line, without its '\n'
      return;
    }
    std::memmove(buffer.data(), text.data(), text.size());
    held = text.size();
  }
}

}  // namespace sphray::particles::detail
