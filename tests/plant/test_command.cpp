// The command as a function of time (zero-order hold / linear) and the streaming simulator's
// real-time properties.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/plant/command.hpp"
#include "clearshape/plant/simulation.hpp"
#include "support/alloc_counter.hpp"

namespace cp = clearshape::plant;

TEST(Command, ZeroOrderHoldAndLinear) {
  clearshape::UniformSeries s;
  s.start_s = 0.0;
  s.sample_time_s = 0.1;
  s.values = {0.0, 1.0, 1.0, 3.0};
  const cp::Command zoh(s);
  EXPECT_EQ(zoh.value(-1.0), 0.0);
  EXPECT_EQ(zoh.value(0.05), 0.0);
  EXPECT_EQ(zoh.value(0.1), 1.0);  // right-continuous at the knot
  EXPECT_EQ(zoh.value(0.3 * (1.0 - 1e-13)), 3.0);  // within rounding of the knot 3·0.1
  EXPECT_EQ(zoh.value(0.25), 1.0);
  EXPECT_EQ(zoh.value(10.0), 3.0);
  EXPECT_EQ(zoh.rate(0.15), 0.0);
  ASSERT_EQ(zoh.discontinuities_s().size(), 2u);  // 0.1 and 0.3 (1.0 → 1.0 is no jump)
  EXPECT_NEAR(zoh.next_discontinuity_s(0.0), 0.1, 1e-15);
  EXPECT_NEAR(zoh.next_discontinuity_s(0.1), 0.3, 1e-15);
  EXPECT_TRUE(std::isinf(zoh.next_discontinuity_s(0.3)));
  const cp::Command lin(s, cp::Interpolation::linear);
  EXPECT_NEAR(lin.value(0.05), 0.5, 1e-15);
  EXPECT_NEAR(lin.value(0.25), 2.0, 1e-15);
  EXPECT_NEAR(lin.rate(0.25), 20.0, 1e-12);
  EXPECT_EQ(lin.value(1.0), 3.0);
  EXPECT_TRUE(lin.discontinuities_s().empty());
  s.values[2] = std::nan("");
  EXPECT_THROW(cp::Command{s}, clearshape::InvalidArgument);
  s.values.clear();
  EXPECT_THROW(cp::Command{s}, clearshape::InvalidArgument);
}

// A linearly interpolated ramp drives the motor like the same ramp sampled finely with a hold.
TEST(Command, LinearRampMatchesFineHold) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::first_order_position(0.02);
  m.link.inertia_kg_m2 = 1e-3;
  cp::TorsionalClearance j;
  j.half_play_rad = 1.0;
  m.joint = j;
  clearshape::UniformSeries coarse;
  coarse.sample_time_s = 0.1;
  coarse.values = {0.0, 10.0, 10.0};
  cp::SimulationOptions o;
  o.duration_s = 0.3;
  o.output_rate_hz = 100.0;
  o.solver.relative_tolerance = 1e-10;
  const auto r = cp::simulate(m, cp::Command(coarse, cp::Interpolation::linear), o);
  // exact: θ/unit for u = 100 t (t < 0.1): 100 (t − τ(1 − e^(−t/τ)))
  const double tau = 0.02;
  for (std::size_t k = 0; k <= 10; ++k) {
    const double t = r.time_s[k];
    EXPECT_NEAR(clearshape::rad_to_deg(r.motor_angle_rad[k]), 100.0 * (t - tau * (1.0 - std::exp(-t / tau))), 1e-7);
  }
}

// Simulator::advance is noexcept and, once running, allocation-free (the rig's real-time tick).
TEST(Command, StreamingAdvanceIsAllocationFree) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::thesis_position_mode();
  m.link.inertia_kg_m2 = 1e-3;
  cp::TorsionalClearance j;
  j.half_play_rad = 0.005;
  j.law = cp::ContactLaw::hertz_dashpot(1e4, 1.5, 300.0, cp::DampingPolicy::clamped);
  m.joint = j;
  cp::Simulator sim(m);
  ASSERT_EQ(sim.advance(0.001, 0.0), clearshape::Status::ok);
  clearshape::testing::AllocationCounter counter;
  for (int k = 2; k <= 300; ++k) {
    const double command = k < 50 ? 0.0 : 10.0 + 0.01 * k;  // changes every tick: restarts
    ASSERT_EQ(sim.advance(0.001 * k, command), clearshape::Status::ok);
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_GT(sim.stats().events, 0);
  EXPECT_GT(sim.state().link_angle_rad, 0.1);
}
