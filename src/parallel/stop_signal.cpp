#include "parallel/stop_signal.hpp"

#include <atomic>
#include <csignal>

namespace cs {
namespace {

// Written by the handler, read by every thread: it must be lock-free to be async-signal-safe.
std::atomic<int> received{0};
static_assert(std::atomic<int>::is_always_lock_free);

void set_action(int signal, void (*handler)(int)) {
  struct sigaction action = {};
  action.sa_handler = handler;
  sigemptyset(&action.sa_mask);
  // SA_RESTART: a system call in progress (a journal write, an fsync, a read of a compiler's
  // pipe) goes on instead of failing with EINTR, which would turn a clean stop into a failure.
  action.sa_flags = SA_RESTART;
  ::sigaction(signal, &action, nullptr);
}

void on_stop_signal(int signal) {
  int none = 0;
  received.compare_exchange_strong(none, signal);  // the first signal is the one reported
  // A second SIGTERM or SIGINT, of either kind, ends the process at once (sigaction is
  // async-signal-safe).
  set_action(SIGTERM, SIG_DFL);
  set_action(SIGINT, SIG_DFL);
}

}  // namespace

void install_stop_signal_handler() {
  set_action(SIGTERM, on_stop_signal);
  set_action(SIGINT, on_stop_signal);
}

int stop_signal() { return received.load(); }

const char* stop_signal_name(int signal) {
  switch (signal) {
    case SIGTERM: return "SIGTERM";
    case SIGINT: return "SIGINT";
    default: return "a signal";
  }
}

}  // namespace cs
