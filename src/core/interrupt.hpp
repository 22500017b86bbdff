#pragma once
// Graceful interruption of long runs. install_interrupt_handlers() makes SIGINT and SIGTERM set a flag
// instead of killing the process: the run stops at its next frame boundary, writes what it has and exits with
// 128 + the signal (130 for SIGINT, 143 for SIGTERM). A second signal ends the process at once with that
// code. Only commands that check the flag opt in (set_graceful_interrupts(true)); for the others a signal
// keeps its default action (the process ends at once).
#include <csignal>

namespace glmbslam {

/// Installs the SIGINT/SIGTERM handlers (idempotent).
void install_interrupt_handlers();

/// Whether a first signal only sets the flag (true) or ends the process as by default (false, the initial
/// mode).
void set_graceful_interrupts(bool graceful);

/// True once SIGINT or SIGTERM has been received (or request_interrupt() called).
bool interrupt_requested();

/// The signal received (SIGINT or SIGTERM), 0 if none.
int interrupt_signal();

/// Process exit code for an interrupted run: 128 + the signal (130 SIGINT, 143 SIGTERM), 0 if none.
int interrupt_exit_code();

/// Sets the flag as a signal would (for tests and for callers that stop a run themselves).
void request_interrupt(int signal = SIGTERM);

/// Clears the flag (for tests).
void clear_interrupt();

}  // namespace glmbslam
