#include "temp_registry.hpp"

#include <atomic>
#include <csignal>
#include <cstring>

#include <unistd.h>

#include "clearshape/io/atomic_file.hpp"

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

extern "C" void on_terminating_signal(int signo) {
  for (auto& slot : g_slots) {
    if (slot.state.load() == 2) ::unlink(slot.path);
  }
  std::signal(signo, SIG_DFL);
  std::raise(signo);
}

}  // namespace
}  // namespace detail

void install_signal_cleanup() {
  struct sigaction action {};
  action.sa_handler = detail::on_terminating_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = 0;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace clearshape::io
