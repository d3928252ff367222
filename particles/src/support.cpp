// What the particle readers share (support.hpp).
#include "support.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <utility>

namespace sphray::particles::detail {
namespace {

[[noreturn]] void refuse_errno(const std::string& source, int error) {
  throw ParticleError(source + ": cannot read the particle file (" + std::strerror(error) + ")");
}

template <typename T>
std::string shortest_of(T value) {
  char text[32];
  const auto result = std::to_chars(text, text + sizeof text, value);
  return std::string(text, result.ptr);
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
  return shortest_of(value);
}

std::string shortest(double value) {
  return shortest_of(value);
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

namespace {

template <typename T>
std::optional<T> as_number_of(std::string_view field, bool& out_of_range) {
  out_of_range = false;
  // A leading '+' (printf's %+g) is a sign; from_chars takes only '-'.
  if (field.starts_with('+')) {
    field.remove_prefix(1);
    if (field.starts_with('+') || field.starts_with('-')) return std::nullopt;  // "+-1"
  }
  T value = 0;
  const char* end = field.data() + field.size();
  const auto [stop, error] = std::from_chars(field.data(), end, value);
  out_of_range = error == std::errc::result_out_of_range && stop == end;
  if (error != std::errc{} || stop != end) return std::nullopt;
  return value;
}

}  // namespace

std::optional<float> as_number(std::string_view field, bool& out_of_range) {
  return as_number_of<float>(field, out_of_range);
}

std::optional<double> as_double(std::string_view field, bool& out_of_range) {
  return as_number_of<double>(field, out_of_range);
}

const char* coordinate_problem(float value, bool radius) {
  if (!std::isfinite(value)) return "to be finite";
  if (radius && !(value > 0)) return "to be positive";
  if (std::abs(value) > kMaxMagnitude) return "at most 1e17 in magnitude";
  return nullptr;
}

void check_radius_option(const std::string& source, const PointOptions& options) {
  if (options.radius && !(std::isfinite(*options.radius) && *options.radius > 0 &&
                          *options.radius <= kMaxMagnitude)) {
    throw ParticleError(source +
                        ": expected the radius given for the file to be positive and at most "
                        "1e17, got " +
                        shortest(*options.radius));
  }
}

Closing::~Closing() {
  if (fd >= 0) ::close(fd);
}

int open_regular(const std::filesystem::path& path, std::uint64_t& size) {
  const std::string source = path.string();
  // O_NONBLOCK: opening a FIFO would otherwise wait for a writer; only regular files are read.
  Closing fd{::open(path.c_str(), O_RDONLY | O_CLOEXEC | O_NOCTTY | O_NONBLOCK)};
  if (fd.fd < 0) refuse_errno(source, errno);
  struct stat st {};
  if (::fstat(fd.fd, &st) != 0) refuse_errno(source, errno);
  if (S_ISDIR(st.st_mode))
    throw ParticleError(source + ": expected a particle file, got a directory");
  if (!S_ISREG(st.st_mode)) throw ParticleError(source + ": expected a regular file");
  size = static_cast<std::uint64_t>(st.st_size);
  return std::exchange(fd.fd, -1);
}

std::size_t read_some(int fd, char* data, std::size_t size, const std::string& source) {
  std::size_t got = 0;
  while (got < size) {
    const ssize_t n = ::read(fd, data + got, size - got);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) refuse_errno(source, errno);
    if (n == 0) break;
    got += static_cast<std::size_t>(n);
  }
  return got;
}

}  // namespace sphray::particles::detail
