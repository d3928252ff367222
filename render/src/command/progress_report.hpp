// What `sphray render` says on stderr while it works: the phase it is in (making or reading the
// scene, building the tree, rendering, writing the image), the time since it started and, while
// rendering, the part done, the rate over the tracing alone and the time left.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "sphray/render/renderer.hpp"

namespace sphray::render::progress {

/// A rate always in Mrays/s (never switching units): two decimals, more below 1 Mrays/s so that
/// three digits show ("0.000070 Mrays/s").
std::string rate_text(double rays_per_second);

/// A duration for people: "0.4 s", "12 s", "2 min 05 s", "1 h 02 min".
std::string duration_text(double seconds);

/// Where the renderer is, as the progress line shows it.
struct Snapshot {
  std::string phase;         // "building the tree of 8000000 spheres", "rendering", ...
  double elapsed = 0;        // seconds since the command started
  bool rendering = false;    // the fields below are set
  std::size_t done = 0;      // tiles (path mode: tiles times samples) finished
  std::size_t total = 0;     // of that many
  RayCounts rays;            // traced so far
  double trace_seconds = 0;  // since the first tile started (the tree's build excluded)
  double time_limit = 0;     // path mode's --time-limit, 0 for none
};

/// The seconds left by the rate so far, capped by a time limit; negative when unknown.
double seconds_left(const Snapshot& s);

/// The line a terminal shows: the phase, for the render a bar, percent, rays by kind, rate and
/// time left, then the elapsed time.
std::string terminal_line(const Snapshot& s);

/// The line a log gets (stderr not a terminal): "sphray: rendering: 45%, ..., 12 s elapsed".
std::string log_line(const Snapshot& s);

/// Reports the phases on stderr. On a terminal one line, redrawn ten times a second by a thread
/// of its own (so the elapsed time moves during a tree's build, which reports nothing) and at
/// once when a phase starts. Elsewhere (a pipe, a file) plain lines, no control characters and
/// none for a run that ends quickly: a phase that has run kLogAfter gets one, the render one
/// every kLogEvery. Disabled (--quiet) it prints nothing and starts no thread.
class Reporter {
 public:
  static constexpr std::chrono::seconds kLogAfter{2};
  static constexpr std::chrono::seconds kLogEvery{10};

  Reporter(bool enabled, bool terminal, double time_limit = 0);
  ~Reporter();  // stops the thread and clears the terminal's line
  Reporter(const Reporter&) = delete;
  Reporter& operator=(const Reporter&) = delete;

  /// A new phase (main thread): drawn at once on a terminal.
  void phase(std::string name);
  /// The renderer's progress callback (worker threads): its first call, done 0, starts the
  /// render phase and its clock.
  void update(std::size_t done, std::size_t total, const RayCounts& rays);
  /// Clears the terminal's line before the summary is printed.
  void finish();

 private:
  using Clock = std::chrono::steady_clock;
  Snapshot snapshot() const;     // under mutex_
  void draw(const Snapshot& s);  // under mutex_
  void run(std::stop_token stop);

  const bool enabled_;
  const bool terminal_;
  const double time_limit_;
  const Clock::time_point start_ = Clock::now();
  mutable std::mutex mutex_;
  std::condition_variable_any wake_;
  std::string phase_;
  Clock::time_point phase_start_ = start_;
  Clock::time_point last_log_ = start_;
  bool phase_logged_ = false;
  bool shown_ = false;
  // Written by the workers without the lock: the largest values reported so far.
  std::atomic<bool> rendering_{false};
  std::atomic<Clock::rep> trace_start_{0};
  std::atomic<std::size_t> done_{0}, total_{0};
  std::atomic<std::uint64_t> camera_{0}, bounce_{0}, shadow_{0};
  std::jthread thread_;  // last: started once the members above exist
};

}  // namespace sphray::render::progress
