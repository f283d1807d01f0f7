#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <vector>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/rig/offline.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/rig/truth.hpp"
#include "rig_trace.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;
using cs::Status;

namespace {
using Trace = clearshape::testing::RigTrace;
// Runs `samples` cycles: read, then write command(t).
template <class F>
Trace run_loop(rig::Rig& r, std::size_t samples, F command) {
  return clearshape::testing::run_rig_loop(r, samples, command);
}
}  // namespace

TEST(SimRig, PositionStepReachesTheTargetThroughThePulseTrain) {
  rig::SimRig r({});
  ASSERT_EQ(r.configure(), Status::ok);
  ASSERT_EQ(r.activate(), Status::ok);
  const auto trace = run_loop(r, 2001, [](double t) {
    return rig::Command::position_deg(t >= 0.1 ? 10.0 : 0.0);
  });
  // Final motor angle: Kp·10° = 9.959° (thesis Eq. 4.2), to one encoder count plus one pulse.
  const double final_deg = static_cast<double>(trace.counts.back()) * 360.0 / 12000.0;
  EXPECT_NEAR(final_deg, 9.959, 0.03 + 0.12);
  EXPECT_GT(r.contact_events(), 0u);
  EXPECT_EQ(r.counters().failed_reads, 0u);
}

TEST(SimRig, ReadAndWriteNeverAllocate) {
  rig::SimRig r({});
  r.configure();
  r.activate();
  rig::Measurement m;
  cs::testing::AllocationCounter counter;
  for (int k = 0; k < 1500; ++k) {  // a 15° step at 0.05 s: impacts in the play
    ASSERT_EQ(r.read(m), Status::ok);
    r.write(rig::Command::position_deg(k >= 50 ? 15.0 : 0.0));
  }
  EXPECT_EQ(counter.allocations(), 0u);
  EXPECT_GT(r.contact_events(), 0u);

  rig::SimRigOptions speed;
  speed.mode = rig::CommandMode::speed;
  rig::SimRig s(speed);
  s.configure();
  s.activate();
  cs::testing::AllocationCounter speed_counter;
  for (int k = 0; k < 1500; ++k) {  // D/A path, a step beyond the ±10 V range (clipped)
    ASSERT_EQ(s.read(m), Status::ok);
    s.write(rig::Command::speed_v(k >= 50 ? 12.0 : 0.0));
  }
  EXPECT_EQ(speed_counter.allocations(), 0u);
  EXPECT_TRUE(m.has(rig::MeasurementFlag::command_limited));
}

TEST(SimRig, SeedsMakeRunsRepeatableAndDistinct) {
  const auto command = [](double t) { return rig::Command::speed_v(t >= 0.05 ? 1.0 : 0.0); };
  rig::SimRigOptions options;
  options.mode = rig::CommandMode::speed;
  rig::SimRig a(options), b(options);
  a.configure();
  b.configure();
  a.activate();
  b.activate();
  const auto ta = run_loop(a, 300, command);
  const auto tb = run_loop(b, 300, command);
  EXPECT_EQ(ta.gyro, tb.gyro);
  // A second activation is a new repetition: new noise and a new initial position in the play.
  a.deactivate();
  a.activate();
  const auto ta2 = run_loop(a, 300, command);
  EXPECT_NE(ta.gyro, ta2.gyro);
}

// The streamed rig and the offline run are the same model: in speed mode (no look-ahead
// difference) the encoder counts and gyroscope words agree to one count / one LSB (the two
// integrations restart at different points, within CVODE's tolerances).
TEST(SimRig, StreamingMatchesTheOfflineRunInSpeedMode) {
  rig::RigTruth truth = rig::thesis_rig_truth();
  truth.gyro.noise_density_dps_per_rthz = 0.0;
  truth.random_initial_play = false;
  truth.initial_play_fraction = 0.3;
  truth.variation = rig::RunVariation{};  // simulate_run runs the nominal rig
  rig::SimRigOptions options;
  options.mode = rig::CommandMode::speed;
  auto r = rig::make_sim_rig_with_truth(options, truth);
  r->configure();
  r->activate();
  const auto volts = [](double t) { return t >= 0.1 - 1e-12 ? 1.5 : 0.0; };
  const auto streamed = run_loop(*r, 1001, [&](double t) { return rig::Command::speed_v(volts(t)); });

  cs::UniformSeries command;
  command.sample_time_s = 1e-3;
  for (int k = 0; k <= 1000; ++k) command.values.push_back(volts(k * 1e-3));
  rig::RunOptions run_options;
  run_options.duration_s = 1.0;
  run_options.initial_play_fraction = 0.3;
  const auto offline = rig::simulate_run(truth, rig::CommandMode::speed, command, run_options);
  ASSERT_EQ(offline.encoder_counts.size(), streamed.counts.size());
  for (std::size_t k = 0; k < streamed.counts.size(); ++k) {
    EXPECT_LE(std::abs(offline.encoder_counts[k] - streamed.counts[k]), 1) << k;
    EXPECT_LE(std::abs(offline.gyro_raw[k] - streamed.gyro[k]), 1) << k;
  }
  EXPECT_GT(offline.simulation.stats.events, 0);
}

TEST(SimRig, ZeroClearanceGyroReadsTheMotorRate) {
  rig::RigTruth truth = rig::thesis_rig_truth();
  truth.clearance_rad = 0.0;
  truth.gyro.noise_density_dps_per_rthz = 0.0;
  rig::SimRigOptions options;
  options.mode = rig::CommandMode::speed;
  auto r = rig::make_sim_rig_with_truth(options, truth);
  r->configure();
  r->activate();
  const auto trace = run_loop(*r, 2001, [](double) { return rig::Command::speed_v(1.0); });
  EXPECT_EQ(r->contact_events(), 0u);
  // Steady motor speed 25.47 °/s per V (Eq. 4.2) → 25.47·14.375 = 366 LSB.
  EXPECT_NEAR(trace.gyro.back(), 25.47 * 14.375, 1.0);
}

TEST(SimRig, WallClockPacingWaitsAndCounts) {
  rig::SimRigOptions options;
  options.pacing = rig::Pacing::wall_clock;
  rig::SimRig r(options);
  r.configure();
  r.activate();
  const auto begin = std::chrono::steady_clock::now();
  run_loop(r, 51, [](double) { return rig::Command::position_deg(0.0); });
  const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  EXPECT_GE(elapsed_s, 0.050);  // sample 50 is due at 50 ms (a lower bound only)
  EXPECT_EQ(r.pacing_stats().cycles, 51u);
}

TEST(SimRig, RejectsTheOtherModeAndBadOptions) {
  rig::SimRig r({});
  r.configure();
  r.activate();
  EXPECT_EQ(r.write(rig::Command::speed_v(1.0)), Status::out_of_range);
  rig::Measurement m;
  r.read(m);
  EXPECT_TRUE(m.has(rig::MeasurementFlag::command_rejected));
  rig::SimRigOptions bad;
  bad.sample_rate_hz = 0.0;
  rig::SimRig s(bad);
  EXPECT_THROW(s.configure(), cs::InvalidArgument);
  EXPECT_EQ(s.state(), rig::LifecycleState::unconfigured);
}
