#include "core/interrupt.hpp"

#include <unistd.h>

#include <atomic>

namespace glmbslam {
namespace {

std::atomic<int> g_signal{0};
std::atomic<bool> g_graceful{false};
static_assert(std::atomic<int>::is_always_lock_free, "the signal flag must be async-signal-safe");
static_assert(std::atomic<bool>::is_always_lock_free, "the mode flag must be async-signal-safe");

extern "C" void on_interrupt_signal(int signal) {
  if (!g_graceful.load()) {
    // The running command does not stop at frame boundaries: the default action (terminate by the signal).
    std::signal(signal, SIG_DFL);
    std::raise(signal);
    return;
  }
  int expected = 0;
  if (!g_signal.compare_exchange_strong(expected, signal)) {
    // Second signal: the user (or scheduler) insists; stop now without unwinding (async-signal-safe).
    _exit(128 + signal);
  }
  static const char message[] =
      "\nglmbslam: interrupted; finishing the current frame and writing the outputs "
      "(signal again to abort at once)\n";
  const ssize_t ignored = write(STDERR_FILENO, message, sizeof(message) - 1);
  (void)ignored;
}

}  // namespace

void install_interrupt_handlers() {
  struct sigaction action {};
  action.sa_handler = on_interrupt_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESTART;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

void set_graceful_interrupts(bool graceful) {
  g_graceful.store(graceful);
}

bool interrupt_requested() {
  return g_signal.load(std::memory_order_relaxed) != 0;
}

int interrupt_signal() {
  return g_signal.load(std::memory_order_relaxed);
}

int interrupt_exit_code() {
  const int s = interrupt_signal();
  return s == 0 ? 0 : 128 + s;
}

void request_interrupt(int signal) {
  int expected = 0;
  g_signal.compare_exchange_strong(expected, signal);
}

void clear_interrupt() {
  g_signal.store(0);
}

}  // namespace glmbslam
