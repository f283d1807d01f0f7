#pragma once
// Test helper: drive a rig for a number of cycles (read, then write command(t)) and keep what it
// measured.
#include <gtest/gtest.h>

#include <cstddef>
#include <cstdint>
#include <vector>

#include "clearshape/rig/rig.hpp"

namespace clearshape::testing {

struct RigTrace {
  std::vector<std::int64_t> counts;
  std::vector<std::int16_t> gyro;
  std::vector<double> gyro_rate;
  std::vector<std::uint32_t> flags;
};

template <class F>
RigTrace run_rig_loop(rig::Rig& r, std::size_t samples, F command) {
  RigTrace t;
  rig::Measurement m;
  for (std::size_t k = 0; k < samples; ++k) {
    EXPECT_EQ(r.read(m), Status::ok) << k;
    t.counts.push_back(m.encoder_counts);
    t.gyro.push_back(m.gyro_raw);
    t.gyro_rate.push_back(m.gyro_rate_rad_s);
    t.flags.push_back(m.flags);
    r.write(command(m.time_s));
  }
  return t;
}

}  // namespace clearshape::testing
