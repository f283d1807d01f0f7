// parallel_for (core/parallel.hpp): every index runs once, and the error rethrown is that of the
// lowest failing index whatever the timing (a later index that fails first does not win).
#include <gtest/gtest.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "clearshape/core/parallel.hpp"

TEST(ParallelFor, EveryIndexRunsOnceOnAnyThreadCount) {
  for (const int threads : {0, 1, 2, 7, 64}) {
    std::vector<int> runs(100, 0);
    clearshape::parallel_for(runs.size(), threads, [&](std::size_t k) { ++runs[k]; });
    EXPECT_EQ(runs, std::vector<int>(100, 1)) << threads << " thread(s)";
  }
  clearshape::parallel_for(0, 4, [](std::size_t) { FAIL() << "no index to run"; });
}

TEST(ParallelFor, TheLowestFailingIndexWinsEvenWhenItFailsLast) {
  // Index 0 fails after 0.1 s, index 1 at once; index 0 is the one reported, every time.
  for (int repeat = 0; repeat < 3; ++repeat) {
    std::vector<int> ran(8, 0);
    try {
      clearshape::parallel_for(ran.size(), 3, [&](std::size_t k) {
        ran[k] = 1;
        if (k == 0) std::this_thread::sleep_for(std::chrono::milliseconds(100));
        if (k <= 1) throw std::runtime_error("index " + std::to_string(k));
      });
      FAIL() << "no error rethrown";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "index 0");
    }
    EXPECT_EQ(ran[0], 1);
    EXPECT_EQ(ran[1], 1);
  }
}

TEST(ParallelFor, OneThreadStopsAtTheFirstError) {
  std::vector<int> ran(5, 0);
  EXPECT_THROW(clearshape::parallel_for(ran.size(), 1,
                                        [&](std::size_t k) {
                                          ran[k] = 1;
                                          if (k == 2) throw std::runtime_error("stop");
                                        }),
               std::runtime_error);
  EXPECT_EQ(ran, (std::vector<int>{1, 1, 1, 0, 0}));
}
