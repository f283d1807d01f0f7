#pragma once
// Deferred interrupts: a job that must finish a step before the process ends (a rig that must
// be sent STOP and switched off) turns SIGINT, SIGTERM, SIGHUP and SIGPIPE into a request it
// polls, instead of an immediate end.
//
//   io::DeferredInterrupts scope;                 // from here, the signals are only recorded
//   runner_options.stop_flag = &io::interrupt_requested();
//   ... the loop ends at the next cycle; the rig is stopped; the record written ...
//   scope.end_process_if_interrupted();          // then the signal ends the process as usual
//
// The handler (async-signal-safe: atomics and write(2) only) records the first signal, sets the
// flag and prints one line on stderr. Outside a scope the same signals remove the temporary
// files in flight and end the process (install_signal_cleanup, io/atomic_file.hpp).
#include <atomic>

namespace clearshape::io {

/// Set by the first SIGINT/SIGTERM/SIGHUP/SIGPIPE inside a DeferredInterrupts scope; loops poll it
/// (lock-free, real-time safe).
const std::atomic<bool>& interrupt_requested() noexcept;
/// The signal recorded (0: none).
int pending_interrupt() noexcept;

class DeferredInterrupts {
 public:
  /// Installs the handlers (install_signal_cleanup) and starts deferring; clears a previous
  /// request. One scope at a time (a nested one throws RuntimeError).
  DeferredInterrupts();
  /// Stops deferring; a recorded signal is forgotten unless end_process_if_interrupted ran.
  ~DeferredInterrupts();
  DeferredInterrupts(const DeferredInterrupts&) = delete;
  DeferredInterrupts& operator=(const DeferredInterrupts&) = delete;
  /// When a signal was recorded: removes the temporaries in flight and ends the process by that
  /// signal (its default action: the shell sees 130 for SIGINT, 143 for SIGTERM). Else returns.
  void end_process_if_interrupted();
};

/// "SIGINT", "SIGTERM", … for the signals above ("a signal" otherwise).
const char* interrupt_name(int signo) noexcept;

}  // namespace clearshape::io
