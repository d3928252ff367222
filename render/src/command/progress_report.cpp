#include "command/progress_report.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <system_error>

namespace sphray::render::progress {
namespace {

// Stores value if it is larger: the workers report out of order.
template <typename T>
void store_max(std::atomic<T>& a, T value) {
  T seen = a.load(std::memory_order_relaxed);
  while (seen < value && !a.compare_exchange_weak(seen, value, std::memory_order_relaxed)) {
  }
}

std::string millions(std::uint64_t n) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1fM", static_cast<double>(n) / 1e6);
  return text;
}

std::string rays_text(const RayCounts& r) {
  std::string text = millions(r.camera) + " camera";
  if (r.bounce > 0) text += " + " + millions(r.bounce) + " bounce";
  if (r.shadow > 0) text += " + " + millions(r.shadow) + " shadow";
  return text + " rays";
}

double rate(const Snapshot& s) {
  const std::uint64_t all = s.rays.camera + s.rays.bounce + s.rays.shadow;
  return s.trace_seconds > 0 ? static_cast<double>(all) / s.trace_seconds : 0.0;
}

int percent(const Snapshot& s) {
  return s.total > 0 ? static_cast<int>(100 * std::min(s.done, s.total) / s.total) : 0;
}

// ", 11.20 Mrays/s, about 5 s left" once a tile has finished.
std::string rate_and_left(const Snapshot& s) {
  if (s.done == 0) return {};
  std::string text = ", " + rate_text(rate(s));
  const double left = seconds_left(s);
  if (left >= 0) text += ", about " + duration_text(left) + " left";
  return text;
}

// The terminal's width, 0 if it does not say.
std::size_t terminal_columns() {
  winsize size{};
  return ::ioctl(STDERR_FILENO, TIOCGWINSZ, &size) == 0 ? size.ws_col : 0;
}

}  // namespace

std::string rate_text(double rays_per_second) {
  const double m = std::max(0.0, rays_per_second) / 1e6;
  int decimals = 2;
  if (m > 0 && m < 1) decimals = std::min(6, 2 - static_cast<int>(std::floor(std::log10(m))));
  char text[48];
  std::snprintf(text, sizeof text, "%.*f Mrays/s", decimals, m);
  return text;
}

std::string duration_text(double seconds) {
  char text[32];
  seconds = std::max(0.0, seconds);
  if (seconds < 10) {
    std::snprintf(text, sizeof text, "%.1f s", seconds);
  } else if (seconds < 60) {
    std::snprintf(text, sizeof text, "%.0f s", seconds);
  } else if (seconds < 3600) {
    const long s = std::lround(seconds);
    std::snprintf(text, sizeof text, "%ld min %02ld s", s / 60, s % 60);
  } else {
    const long m = std::lround(seconds / 60);
    std::snprintf(text, sizeof text, "%ld h %02ld min", m / 60, m % 60);
  }
  return text;
}

double seconds_left(const Snapshot& s) {
  if (!s.rendering || s.done == 0 || s.total == 0 || s.trace_seconds <= 0) return -1;
  const double done = static_cast<double>(std::min(s.done, s.total));
  double left = s.trace_seconds * (static_cast<double>(s.total) - done) / done;
  if (s.time_limit > 0) left = std::min(left, std::max(0.0, s.time_limit - s.trace_seconds));
  return left;
}

std::string terminal_line(const Snapshot& s) {
  const std::string elapsed = duration_text(s.elapsed) + " elapsed";
  if (!s.rendering) return s.phase + " ... " + elapsed;
  constexpr int kWidth = 24;
  const int filled = kWidth * percent(s) / 100;
  char head[16];
  std::snprintf(head, sizeof head, "] %3d%% ", percent(s));
  return s.phase + " [" + std::string(static_cast<std::size_t>(filled), '#') +
         std::string(static_cast<std::size_t>(kWidth - filled), ' ') + head + rays_text(s.rays) +
         rate_and_left(s) + ", " + elapsed;
}

std::string log_line(const Snapshot& s) {
  const std::string elapsed = duration_text(s.elapsed) + " elapsed";
  if (!s.rendering) return "sphray: " + s.phase + ", " + elapsed;
  return "sphray: " + s.phase + ": " + std::to_string(percent(s)) + "%, " + rays_text(s.rays) +
         rate_and_left(s) + ", " + elapsed;
}

Reporter::Reporter(bool enabled, bool terminal, double time_limit)
    : enabled_(enabled), terminal_(terminal), time_limit_(time_limit) {
  if (!enabled_) return;
  try {
    thread_ = std::jthread([this](std::stop_token stop) { run(stop); });
  } catch (const std::system_error&) {
    // No thread to be had (a process limit): the phases are still drawn as they start.
  }
}

Reporter::~Reporter() {
  finish();
}

void Reporter::phase(std::string name) {
  if (!enabled_) return;
  const std::lock_guard lock(mutex_);
  phase_ = std::move(name);
  phase_start_ = Clock::now();
  rendering_ = false;  // the render's own phase starts with its first update
  phase_logged_ = false;
  if (terminal_) draw(snapshot());
}

void Reporter::update(std::size_t done, std::size_t total, const RayCounts& rays) {
  if (!enabled_) return;
  store_max(done_, done);
  store_max(total_, total);
  store_max(camera_, rays.camera);
  store_max(bounce_, rays.bounce);
  store_max(shadow_, rays.shadow);
  if (done == 0 && !rendering_.load()) {  // called once, before the first tile
    const std::lock_guard lock(mutex_);
    const Clock::time_point now = Clock::now();
    trace_start_ = now.time_since_epoch().count();
    rendering_ = true;
    phase_ = "rendering";
    phase_start_ = now;
    last_log_ = now;
    phase_logged_ = false;
    if (terminal_) draw(snapshot());
  }
}

void Reporter::finish() {
  if (thread_.joinable()) {
    thread_.request_stop();
    thread_.join();
  }
  const std::lock_guard lock(mutex_);
  if (shown_) std::fputs("\r\033[K", stderr);
  std::fflush(stderr);
  shown_ = false;
}

Snapshot Reporter::snapshot() const {
  const Clock::time_point now = Clock::now();
  Snapshot s;
  s.phase = phase_;
  s.elapsed = std::chrono::duration<double>(now - start_).count();
  s.rendering = rendering_;
  s.time_limit = time_limit_;
  if (s.rendering) {
    s.done = done_;
    s.total = total_;
    s.rays = {camera_, bounce_, shadow_};
    const Clock::time_point trace_start{Clock::duration(trace_start_.load())};
    s.trace_seconds = std::chrono::duration<double>(now - trace_start).count();
  }
  return s;
}

void Reporter::draw(const Snapshot& s) {
  if (s.phase.empty()) return;
  std::string line = terminal_line(s);
  const std::size_t columns = terminal_columns();
  if (columns > 0 && line.size() >= columns) line.resize(columns - 1);  // a wrapped line stays
  std::fprintf(stderr, "\r%s\033[K", line.c_str());
  std::fflush(stderr);
  shown_ = true;
}

void Reporter::run(std::stop_token stop) {
  const auto period = std::chrono::milliseconds(terminal_ ? 100 : 250);
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait_for(lock, stop, period, [] { return false; });  // a period, or until stopped
    if (stop.stop_requested()) return;
    if (terminal_) {
      draw(snapshot());
      continue;
    }
    if (phase_.empty()) continue;
    const Clock::time_point now = Clock::now();
    const bool first = !phase_logged_ && now - phase_start_ >= kLogAfter;
    const bool again = phase_logged_ && rendering_ && now - last_log_ >= kLogEvery;
    if (!first && !again) continue;
    std::fprintf(stderr, "%s\n", log_line(snapshot()).c_str());
    std::fflush(stderr);
    phase_logged_ = true;
    last_log_ = now;
  }
}

}  // namespace sphray::render::progress
