#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "clearshape/core/error.hpp"
#include "clearshape/rig/pacer.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;

// No upper bounds on time here (never timed assertions): sleep_until guarantees only that a
// deadline is not met early, so the tests check lower bounds and the overrun bookkeeping.
TEST(Pacer, SleepsUntilAbsoluteDeadlines) {
  rig::Pacer pacer(2e-3);
  EXPECT_EQ(pacer.wait(), cs::Status::not_ready);
  const auto begin = std::chrono::steady_clock::now();
  pacer.start();
  cs::testing::AllocationCounter counter;
  for (int i = 0; i < 11; ++i) pacer.wait();  // deadlines 0, 2, …, 20 ms
  EXPECT_EQ(counter.allocations(), 0u);
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  EXPECT_GE(elapsed_s, 20e-3);
  EXPECT_EQ(pacer.stats().cycles, 11u);
}

TEST(Pacer, CountsOverrunsAndSkipsMissedPeriods) {
  rig::Pacer pacer(1e-3);
  pacer.start();
  EXPECT_EQ(pacer.wait(), cs::Status::ok);         // deadline 0: on time
  std::this_thread::sleep_for(std::chrono::milliseconds(5));  // deadline 1 ms passed by ≥ 4 ms
  EXPECT_EQ(pacer.wait(), cs::Status::overrun);
  EXPECT_EQ(pacer.stats().overruns, 1u);
  EXPECT_GE(pacer.stats().missed_periods, 4u);
  EXPECT_GE(pacer.stats().max_lateness_s, 4e-3);
  // After skipping, the next deadline lies in the future: no burst of overruns.
  EXPECT_EQ(pacer.wait(), cs::Status::ok);
}

TEST(Pacer, RejectsBadPeriod) {
  EXPECT_THROW(rig::Pacer(0.0), cs::InvalidArgument);
  EXPECT_THROW(rig::Pacer(20.0), cs::InvalidArgument);
}
