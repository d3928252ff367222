// Ctrl-C during a long call. Python runs its signal handlers (SIGINT's raises KeyboardInterrupt)
// only on the main thread and only while that thread holds the GIL, which a query or render
// has released for its whole length. So the thread that made the call, between two pieces of
// its work, takes the GIL back for a moment now and then and lets Python run the handlers; if
// one raised, the call stops: Interrupted unwinds it (oneTBB cancels the other workers' pieces
// and rethrows it on the calling thread), frees what it made, and the module's translator
// (module.cpp) hands Python the error the handler left.
#pragma once

#include <pybind11/pybind11.h>

#include <chrono>
#include <exception>
#include <thread>

namespace sphray::python {

/// Thrown when a signal handler raised; the Python error it set is still pending.
struct Interrupted : std::exception {
  const char* what() const noexcept override { return "interrupted by a signal"; }
};

/// Made on the calling thread; check() may be called from any thread, and does something only
/// on that one (the others' pieces are cancelled when it throws).
class Interruption {
 public:
  /// How often the calling thread asks: a pause for the GIL this often costs nothing measurable,
  /// and a Ctrl-C is answered well within a second.
  static constexpr std::chrono::milliseconds kEvery{50};

  void check() {
    if (std::this_thread::get_id() != caller_) return;
    const auto now = std::chrono::steady_clock::now();
    if (now - last_ < kEvery) return;
    last_ = now;
    pybind11::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) throw Interrupted();
  }

 private:
  const std::thread::id caller_ = std::this_thread::get_id();
  std::chrono::steady_clock::time_point last_ = std::chrono::steady_clock::now();
};

}  // namespace sphray::python
