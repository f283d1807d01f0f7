// Run-to-run variation of the simulated rig (rig/variation.hpp): the drawn values follow their
// documented distributions (statistical bounds stated per test), a rig without variation
// repeats exactly, the same seed gives the same bytes, the read/write path stays
// allocation-free, and validation names the field, its value and the allowed range.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/rig/variation.hpp"
#include "rig_trace.hpp"
#include "support/alloc_counter.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;
using cs::Status;

namespace {

struct Stats {
  double mean = 0.0, std = 0.0, min = 1e300, max = -1e300;
};
Stats stats(const std::vector<double>& v) {
  Stats s;
  for (double x : v) {
    s.mean += x;
    s.min = std::min(s.min, x);
    s.max = std::max(s.max, x);
  }
  s.mean /= static_cast<double>(v.size());
  for (double x : v) s.std += (x - s.mean) * (x - s.mean);
  s.std = std::sqrt(s.std / static_cast<double>(v.size() - 1));
  return s;
}

using Trace = clearshape::testing::RigTrace;
// Runs `samples` cycles: read, then write command(t).
template <class F>
Trace run(rig::Rig& r, std::size_t samples, F command) {
  return clearshape::testing::run_rig_loop(r, samples, command);
}

// A truth whose sensors and initial play add nothing random.
rig::RigTruth quiet_truth() {
  rig::RigTruth t = rig::thesis_rig_truth();
  t.gyro.noise_density_dps_per_rthz = 0.0;
  t.random_initial_play = false;
  t.variation = rig::RunVariation{};  // each test sets the σ it studies
  return t;
}

}  // namespace

// N = 20000 draws: the sample standard deviation of a normal variable has a relative standard
// error 1/√(2N) = 0.5 %; bounds at 3 % (6σ). Uniform latency: mean max/2 with standard error
// max/√(12N) = 0.2 % of max; bound 2 %.
TEST(RunVariation, DrawsFollowTheDocumentedDistributions) {
  rig::RunVariation v;
  v.position_gain_rel_sigma = 1e-3;
  v.speed_gain_rel_sigma = 0.02;
  v.start_latency_max_s = 5e-4;
  v.analog_offset_sigma_v = 0.01;
  v.flank_damping_rel_sigma = 0.2;
  std::mt19937_64 rng(42);
  std::vector<double> pg, sg, lat, off, logd;
  for (int i = 0; i < 20000; ++i) {
    const rig::RunDraw d = rig::draw_run_variation(v, rng);
    pg.push_back(d.position_gain - 1.0);
    sg.push_back(d.speed_gain - 1.0);
    lat.push_back(d.start_latency_s);
    off.push_back(d.analog_offset_v);
    logd.push_back(std::log(d.flank_damping_factor));
  }
  EXPECT_NEAR(stats(pg).std / 1e-3, 1.0, 0.03);
  EXPECT_NEAR(stats(sg).std / 0.02, 1.0, 0.03);
  EXPECT_NEAR(stats(off).std / 0.01, 1.0, 0.03);
  EXPECT_NEAR(stats(logd).std / 0.2, 1.0, 0.03);
  EXPECT_NEAR(stats(pg).mean, 0.0, 5 * 1e-3 / std::sqrt(20000.0));
  EXPECT_NEAR(stats(lat).mean / 5e-4, 0.5, 0.02);
  EXPECT_GE(stats(lat).min, 0.0);
  EXPECT_LT(stats(lat).max, 5e-4);
  EXPECT_LE(stats(sg).max, 4 * 0.02 + 1e-15);  // clipped at ±4σ
}

TEST(RunVariation, ZeroSigmaDrawsAreNeutral) {
  std::mt19937_64 rng(7);
  const rig::RunDraw d = rig::draw_run_variation(rig::RunVariation{}, rng);
  EXPECT_EQ(d.position_gain, 1.0);
  EXPECT_EQ(d.speed_gain, 1.0);
  EXPECT_EQ(d.start_latency_s, 0.0);
  EXPECT_EQ(d.analog_offset_v, 0.0);
  EXPECT_EQ(d.flank_damping_factor, 1.0);
}

// The speed drive's gain scatter shows in the steady speed: with a rigid link and a noise-free
// gyroscope the final speed is Kp·g·1 V, so (speed / mean) − 1 has σ = speed_gain_rel_sigma.
// 120 activations: relative standard error of the sample σ 1/√240 = 6.5 %; bound 25 % (~4σ).
TEST(RunVariation, SpeedGainScatterShowsInTheSteadySpeed) {
  rig::RigTruth t = quiet_truth();
  t.clearance_rad = 0.0;
  t.variation.speed_gain_rel_sigma = 0.02;
  rig::SimRigOptions o;
  o.mode = rig::CommandMode::speed;
  o.seed = 11;
  auto r = rig::make_sim_rig_with_truth(o, t);
  ASSERT_EQ(r->configure(), Status::ok);
  std::vector<double> speeds;
  for (int i = 0; i < 120; ++i) {
    ASSERT_EQ(r->activate(), Status::ok);
    const Trace tr = run(*r, 2500, [](double) { return rig::Command::speed_v(1.0); });
    speeds.push_back(tr.gyro_rate.back());
    r->deactivate();
  }
  const Stats s = stats(speeds);
  EXPECT_NEAR(cs::rad_to_deg(s.mean), 25.47, 25.47 * 0.02 * 4 / std::sqrt(120.0) + 0.1);
  EXPECT_NEAR(s.std / s.mean / 0.02, 1.0, 0.25);
}

// The D/A offset moves the motor at rest: speed = Kp·offset, σ = Kp·analog_offset_sigma_v.
// 120 activations; bound 25 % as above.
TEST(RunVariation, AnalogOffsetDrivesTheMotorAtRest) {
  rig::RigTruth t = quiet_truth();
  t.clearance_rad = 0.0;
  t.variation.analog_offset_sigma_v = 0.02;
  rig::SimRigOptions o;
  o.mode = rig::CommandMode::speed;
  auto r = rig::make_sim_rig_with_truth(o, t);
  r->configure();
  std::vector<double> speeds;
  for (int i = 0; i < 120; ++i) {
    r->activate();
    const Trace tr = run(*r, 2500, [](double) { return rig::Command::speed_v(0.0); });
    speeds.push_back(cs::rad_to_deg(tr.gyro_rate.back()) / 25.47);  // V
    r->deactivate();
  }
  EXPECT_NEAR(stats(speeds).std / 0.02, 1.0, 0.25);
}

// Position mode: the 30 Hz update clock's phase is the drawn latency, so the step's half-way
// crossing (interpolated on the encoder) shifts by up to start_latency_max_s and no more.
TEST(RunVariation, StartLatencyShiftsThePositionStep) {
  rig::RigTruth t = quiet_truth();
  t.clearance_rad = 0.0;
  t.variation.start_latency_max_s = 8e-4;
  rig::SimRigOptions o;
  o.seed = 5;
  auto r = rig::make_sim_rig_with_truth(o, t);
  r->configure();
  std::vector<double> crossings;
  for (int i = 0; i < 30; ++i) {
    r->activate();
    const Trace tr = run(*r, 400, [](double time) { return rig::Command::position_deg(time >= 0.1 - 1e-9 ? 20.0 : 0.0); });
    const double half = 10.0 * 12000.0 / 360.0;  // counts
    for (std::size_t k = 1; k < tr.counts.size(); ++k) {
      const double a = static_cast<double>(tr.counts[k - 1]), b = static_cast<double>(tr.counts[k]);
      if (a < half && b >= half) {
        crossings.push_back((static_cast<double>(k - 1) + (half - a) / (b - a)) * 1e-3);
        break;
      }
    }
    r->deactivate();
  }
  ASSERT_EQ(crossings.size(), 30u);
  const Stats s = stats(crossings);
  // Spread: uniform over 0.8 ms (σ 0.23 ms); the encoder's 0.03° steps at ~400°/s blur by ~0.1 ms.
  EXPECT_GT(s.max - s.min, 0.5e-3);
  EXPECT_LT(s.max - s.min, 0.8e-3 + 0.2e-3);
}

// Without variation (and with a fixed initial play and a noise-free gyroscope) every trial is
// bit-identical; with it the encoder sees different runs.
TEST(RunVariation, ZeroVariationRepeatsBitForBit) {
  rig::RigTruth t = quiet_truth();
  rig::SimRigOptions o;
  o.mode = rig::CommandMode::speed;
  const auto command = [](double time) { return rig::Command::speed_v(time >= 0.05 ? 1.0 : 0.0); };
  auto r = rig::make_sim_rig_with_truth(o, t);
  r->configure();
  r->activate();
  const Trace a = run(*r, 600, command);
  r->deactivate();
  r->activate();
  const Trace b = run(*r, 600, command);
  EXPECT_EQ(a.counts, b.counts);
  EXPECT_EQ(a.gyro, b.gyro);

  t.variation.speed_gain_rel_sigma = 0.01;
  t.variation.analog_noise_v = 1e-3;
  t.variation.start_latency_max_s = 5e-4;
  auto v = rig::make_sim_rig_with_truth(o, t);
  v->configure();
  v->activate();
  const Trace c = run(*v, 600, command);
  v->deactivate();
  v->activate();
  const Trace d = run(*v, 600, command);
  EXPECT_NE(c.counts, d.counts);
}

TEST(RunVariation, SameSeedSameBytes) {
  rig::RigTruth t = rig::thesis_rig_truth();
  t.variation.speed_gain_rel_sigma = 0.01;
  t.variation.analog_noise_v = 2e-3;
  t.variation.analog_offset_sigma_v = 1e-3;
  t.variation.start_latency_max_s = 5e-4;
  t.variation.flank_damping_rel_sigma = 0.2;
  rig::SimRigOptions o;
  o.mode = rig::CommandMode::speed;
  o.seed = 99;
  const auto command = [](double time) { return rig::Command::speed_v(time >= 0.05 ? 1.0 : 0.0); };
  auto a = rig::make_sim_rig_with_truth(o, t);
  auto b = rig::make_sim_rig_with_truth(o, t);
  a->configure();
  b->configure();
  for (int i = 0; i < 2; ++i) {
    a->activate();
    b->activate();
    const Trace ta = run(*a, 500, command), tb = run(*b, 500, command);
    EXPECT_EQ(ta.counts, tb.counts);
    EXPECT_EQ(ta.gyro, tb.gyro);
    a->deactivate();
    b->deactivate();
  }
  o.seed = 100;
  auto c = rig::make_sim_rig_with_truth(o, t);
  c->configure();
  c->activate();
  a->activate();
  EXPECT_NE(run(*a, 500, command).counts, run(*c, 500, command).counts);
}

TEST(RunVariation, ReadAndWriteStayAllocationFree) {
  rig::RigTruth t = rig::thesis_rig_truth();
  t.variation.position_gain_rel_sigma = 1e-4;
  t.variation.speed_gain_rel_sigma = 0.01;
  t.variation.analog_noise_v = 2e-3;
  t.variation.analog_offset_sigma_v = 1e-3;
  t.variation.start_latency_max_s = 5e-4;
  t.variation.flank_damping_rel_sigma = 0.2;
  for (const auto mode : {rig::CommandMode::position, rig::CommandMode::speed}) {
    rig::SimRigOptions o;
    o.mode = mode;
    auto r = rig::make_sim_rig_with_truth(o, t);
    r->configure();
    r->activate();
    rig::Measurement m;
    cs::testing::AllocationCounter counter;
    for (int k = 0; k < 1500; ++k) {
      ASSERT_EQ(r->read(m), Status::ok);
      r->write(mode == rig::CommandMode::position ? rig::Command::position_deg(k >= 50 ? 15.0 : 0.0)
                                                  : rig::Command::speed_v(k >= 50 ? 1.0 : 0.0));
    }
    EXPECT_EQ(counter.allocations(), 0u);
    EXPECT_GT(r->contact_events(), 0u);
  }
}

TEST(RunVariation, ValidationNamesTheFieldValueAndRange) {
  const auto message = [](rig::RigTruth t) -> std::string {
    try {
      t.validate();
    } catch (const cs::InvalidArgument& e) {
      return e.what();
    }
    return "";
  };
  rig::RigTruth t = rig::thesis_rig_truth();
  t.variation.speed_gain_rel_sigma = -0.1;
  std::string m = message(t);
  EXPECT_NE(m.find("truth.variation.speed_gain_rel_sigma"), std::string::npos) << m;
  EXPECT_NE(m.find("-0.1"), std::string::npos) << m;
  t = rig::thesis_rig_truth();
  t.variation.flank_damping_rel_sigma = 2.0;
  EXPECT_NE(message(t).find("flank_damping_rel_sigma"), std::string::npos);
  t = rig::thesis_rig_truth();
  t.variation.analog_noise_v = 0.5;
  EXPECT_NE(message(t).find("analog_noise_v"), std::string::npos);
  t = rig::thesis_rig_truth();
  t.variation.start_latency_max_s = 2e-3;
  EXPECT_NE(message(t).find("start_latency_max_s"), std::string::npos);
  // At most one sample period: 0.8 ms is valid, but not at 2 kHz.
  t = rig::thesis_rig_truth();
  t.variation.start_latency_max_s = 8e-4;
  rig::SimRigOptions o;
  o.sample_rate_hz = 2000.0;
  auto r = rig::make_sim_rig_with_truth(o, t);
  try {
    r->configure();
    ADD_FAILURE() << "configure() accepted a latency beyond one sample period";
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("start_latency_max_s"), std::string::npos) << e.what();
  }
}
