#include "temp_registry.hpp"

#include <atomic>
#include <csignal>
#include <cstdio>
#include <cstring>

#include <pthread.h>

#include <unistd.h>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/interrupt.hpp"

namespace clearshape::io {
namespace detail {
namespace {

constexpr int kSlots = 128;
constexpr std::size_t kPathBytes = 4096;

struct Slot {
  std::atomic<int> state{0};  // 0 free, 1 being filled, 2 holds a path
  char path[kPathBytes]{};
};
Slot g_slots[kSlots];

}  // namespace

int register_temporary(const std::string& path) noexcept {
  if (path.size() >= kPathBytes) return -1;
  for (int i = 0; i < kSlots; ++i) {
    int expected = 0;
    if (g_slots[i].state.compare_exchange_strong(expected, 1)) {
      std::memcpy(g_slots[i].path, path.c_str(), path.size() + 1);
      g_slots[i].state.store(2);
      return i;
    }
  }
  return -1;
}

void release_temporary(int slot) noexcept {
  if (slot >= 0 && slot < kSlots) g_slots[slot].state.store(0);
}

namespace {

// The signals that end a job: an interrupt (Ctrl-C), a termination request (timeout, a batch
// scheduler), a closed terminal and a closed pipe. Each leaves no temporary file behind.
constexpr int kSignals[] = {SIGINT, SIGTERM, SIGHUP, SIGPIPE};

std::atomic<bool> g_deferring{false};
std::atomic<bool> g_interrupted{false};
std::atomic<int> g_signal{0};

void remove_temporaries() noexcept {
  for (auto& slot : g_slots) {
    if (slot.state.load() == 2) ::unlink(slot.path);
  }
}

[[noreturn]] void end_by(int signo) noexcept {
  remove_temporaries();
  std::signal(signo, SIG_DFL);
  sigset_t set;
  sigemptyset(&set);
  sigaddset(&set, signo);
  pthread_sigmask(SIG_UNBLOCK, &set, nullptr);
  std::raise(signo);
  _exit(128 + signo);  // not reached: the default action ends the process
}

extern "C" void on_terminating_signal(int signo) {
  if (g_deferring.load()) {
    int none = 0;
    if (g_signal.compare_exchange_strong(none, signo)) {
      static constexpr char kLine[] = "clearshape: interrupted; stopping first (the run ends at its next cycle)\n";
      const ssize_t ignored = ::write(STDERR_FILENO, kLine, sizeof kLine - 1);
      (void)ignored;
    }
    g_interrupted.store(true);
    return;
  }
  end_by(signo);
}

}  // namespace
}  // namespace detail

void install_signal_cleanup() {
  struct sigaction action {};
  action.sa_handler = detail::on_terminating_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  for (const int signo : detail::kSignals) sigaction(signo, &action, nullptr);
}

const std::atomic<bool>& interrupt_requested() noexcept { return detail::g_interrupted; }
int pending_interrupt() noexcept { return detail::g_signal.load(); }

DeferredInterrupts::DeferredInterrupts() {
  bool expected = false;
  if (!detail::g_deferring.compare_exchange_strong(expected, true)) {
    throw RuntimeError("io::DeferredInterrupts: a scope is already active (one at a time)");
  }
  detail::g_signal.store(0);
  detail::g_interrupted.store(false);
  install_signal_cleanup();
}

DeferredInterrupts::~DeferredInterrupts() {
  detail::g_deferring.store(false);
  detail::g_interrupted.store(false);
  detail::g_signal.store(0);
}

void DeferredInterrupts::end_process_if_interrupted() {
  const int signo = detail::g_signal.load();
  if (signo == 0) return;
  detail::g_deferring.store(false);
  std::fflush(stdout);
  std::fflush(stderr);
  detail::end_by(signo);
}

const char* interrupt_name(int signo) noexcept {
  switch (signo) {
    case SIGINT: return "SIGINT";
    case SIGTERM: return "SIGTERM";
    case SIGHUP: return "SIGHUP";
    case SIGPIPE: return "SIGPIPE";
    default: return "a signal";
  }
}

}  // namespace clearshape::io
