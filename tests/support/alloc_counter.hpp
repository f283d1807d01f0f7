#pragma once
// Counts heap allocations to prove real-time paths allocation-free (after Drake's LimitMalloc
// and Eigen's nomalloc test). Linking this replaces the global operator new/delete.
//
//   clearshape::testing::AllocationCounter counter;
//   shaper.step(x);                       // code under test
//   EXPECT_EQ(counter.allocations(), 0u);
#include <cstddef>

namespace clearshape::testing {

/// Total number of operator new calls in the process so far.
std::size_t total_allocations() noexcept;

class AllocationCounter {
 public:
  AllocationCounter() noexcept : start_(total_allocations()) {}
  std::size_t allocations() const noexcept { return total_allocations() - start_; }

 private:
  std::size_t start_;
};

}  // namespace clearshape::testing
