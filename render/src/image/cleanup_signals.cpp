#include "image/cleanup_signals.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>

#include "sphray/render/image_file.hpp"

namespace sphray::render {
namespace detail {
namespace {

// The slot: state 0 free, 1 being filled or emptied, 2 armed. std::atomic<int> is lock-free,
// so the handler may read it.
std::atomic<int> state{0};
int armed_dir = -1;
char armed_name[256];

// Signals whose default action ends the process and which a process may catch. The faults
// (SIGSEGV, SIGBUS, SIGFPE, SIGILL) and SIGABRT are left alone: they mean a bug, and the
// sanitizers report through them.
constexpr int kSignals[] = {SIGHUP,  SIGINT,  SIGQUIT, SIGTERM,   SIGPIPE, SIGALRM, SIGUSR1,
                            SIGUSR2, SIGXCPU, SIGXFSZ, SIGVTALRM, SIGPROF, SIGIO,   SIGPWR};

extern "C" void remove_armed_and_reraise(int signal) {
  const int saved_errno = errno;
  if (state.load() == 2) ::unlinkat(armed_dir, armed_name, 0);
  errno = saved_errno;
  // SA_RESETHAND restored the default action; the signal is blocked until the handler returns,
  // then delivered again with it.
  ::raise(signal);
}

}  // namespace

bool arm_signal_cleanup(int dir_fd, const char* name) noexcept {
  if (std::strlen(name) >= sizeof armed_name) return false;
  int expected = 0;
  if (!state.compare_exchange_strong(expected, 1)) return false;
  armed_dir = dir_fd;
  std::strcpy(armed_name, name);
  state.store(2);
  return true;
}

void disarm_signal_cleanup() noexcept {
  state.store(0);
}

}  // namespace detail

void remove_temporaries_on_signals() {
  for (int signal : detail::kSignals) {
    struct sigaction current {};
    if (::sigaction(signal, nullptr, &current) != 0) continue;
    // A disposition the caller chose is kept: nohup's ignored SIGHUP stays ignored, and so
    // does any other signal set to SIG_IGN or handled by the embedding program.
    if (current.sa_handler != SIG_DFL || (current.sa_flags & SA_SIGINFO) != 0) continue;
    struct sigaction action {};
    action.sa_handler = detail::remove_armed_and_reraise;
    sigemptyset(&action.sa_mask);
    action.sa_flags = SA_RESETHAND | SA_RESTART;
    ::sigaction(signal, &action, nullptr);
  }
}

}  // namespace sphray::render
