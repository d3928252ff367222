// The line-based readers' shared reading: a line at a time through one fixed buffer.
#include "text_lines.hpp"

#include <algorithm>
#include <cstring>
#include <vector>

#include "sphray/particles/particles.hpp"

namespace sphray::particles::detail {
namespace {

[[noreturn]] void refuse_long_line(const std::string& source, std::uint64_t line) {
  throw ParticleError(source + ":" + std::to_string(line) + ": expected lines of at most " +
                      std::to_string(kMaxLineBytes) + " bytes");
}

}  // namespace

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
  std::uint64_t size = 0;
  const Closing fd{open_regular(file, size)};
  // One buffer: a line that straddles two reads is moved to its front before the next read.
  std::vector<char> buffer(std::size_t{1} << 16);
  std::size_t held = 0;  // bytes of an unfinished line at the front of buffer
  std::uint64_t line = 0;
  for (;;) {
    const std::size_t n = read_some(fd.fd, buffer.data() + held, buffer.size() - held, source);
    const std::size_t filled = held + n;
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
