#pragma once
// A bounded single-producer single-consumer ring of trivially copyable values, lock-free
// (Lamport's ring with acquire/release indices). The storage is allocated once in the
// constructor; push() and pop() are noexcept, wait-free and allocation-free. Exactly one
// thread may push and exactly one (possibly another) may pop.
//
//   SpscRing<Sample> ring(4096);      // capacity rounded up to a power of two
//   ring.push(s);                     // producer: false when full (the value is dropped)
//   Sample out; ring.pop(out);        // consumer: false when empty
#include <atomic>
#include <cstddef>
#include <memory>
#include <new>
#include <type_traits>

namespace clearshape::rig {

template <typename T>
class SpscRing {
  static_assert(std::is_trivially_copyable_v<T>, "SpscRing holds trivially copyable values");

 public:
  /// Allocates max(2, next power of two >= min_capacity) slots.
  explicit SpscRing(std::size_t min_capacity) {
    std::size_t capacity = 2;
    while (capacity < min_capacity) capacity <<= 1;
    slots_ = std::make_unique<T[]>(capacity);
    mask_ = capacity - 1;
  }
  SpscRing(const SpscRing&) = delete;
  SpscRing& operator=(const SpscRing&) = delete;

  /// Producer side. Returns false (and drops `value`) when the ring is full.
  bool push(const T& value) noexcept {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) > mask_) return false;
    slots_[head & mask_] = value;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }
  /// Consumer side. Returns false when the ring is empty.
  bool pop(T& value) noexcept {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (head_.load(std::memory_order_acquire) == tail) return false;
    value = slots_[tail & mask_];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }
  /// Values waiting (exact from either side's thread, approximate from a third).
  std::size_t size() const noexcept {
    return head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire);
  }
  bool empty() const noexcept { return size() == 0; }
  std::size_t capacity() const noexcept { return mask_ + 1; }
  /// Consumer side: drops everything queued.
  void clear() noexcept { tail_.store(head_.load(std::memory_order_acquire), std::memory_order_release); }

 private:
  std::unique_ptr<T[]> slots_;
  std::size_t mask_ = 0;
  alignas(64) std::atomic<std::size_t> head_{0};  // written by the producer
  alignas(64) std::atomic<std::size_t> tail_{0};  // written by the consumer
};

}  // namespace clearshape::rig
