// Signals and drive command paths against tests/golden/gen_signal.py (SciPy/NumPy, an
// independent implementation). Tolerances:
//   shapes            1e-12·max(1, |value|) (same formulas, different arithmetic order; the
//                     S-curve comes from scipy PPoly integration of the jerk)
//   PRBS bits         exact (scipy.signal.max_len_seq with our taps and seed)
//   position path     commanded position exact to 1e-9 deg (whole counts), frequency exact
//   speed path (D/A)  exact to 1e-12 V (codes agree)
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <string>

#include "clearshape/core/units.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/prbs.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/signal/speed_path.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;
using sig::RiseShape;

namespace {

void expect_column(const cs::UniformSeries& ours, const std::vector<double>& golden, double rel_tol,
                   const std::string& what) {
  ASSERT_EQ(ours.size(), golden.size()) << what;
  double worst = 0.0;
  for (std::size_t i = 0; i < golden.size(); ++i) {
    const double err = std::abs(ours.values[i] - golden[i]) / std::max(1.0, std::abs(golden[i]));
    worst = std::max(worst, err);
    ASSERT_LE(err, rel_tol) << what << " at sample " << i << ": " << ours.values[i] << " vs " << golden[i];
  }
  ::testing::Test::RecordProperty(what + "_max_rel_error", std::to_string(worst));
}

cs::UniformSeries to_rad(cs::UniformSeries y) {
  for (double& v : y.values) v = cs::deg_to_rad(v);
  return y;
}

}  // namespace

TEST(Golden, SignalShapes) {
  const auto table = cs::io::read_table(cs::testing::golden_path("signal_shapes.csv"));
  const std::map<std::string, sig::Signal> cases = {
      {"step_ideal", sig::Step{.amplitude = 2.5, .start_s = 0.3}},
      {"step_linear", sig::Step{.amplitude = 10.0, .start_s = 0.25, .rise_s = 0.4}},
      {"step_scurve", sig::Step{.amplitude = -7.0, .start_s = 0.5, .rise_s = 0.6, .rise_shape = RiseShape::s_curve}},
      {"ramp_limited", sig::Ramp{.slope_per_s = 4.0, .start_s = 0.2, .limit = 5.0}},
      {"sine", sig::Sine{.amplitude = 3.0, .frequency_hz = 1.7, .phase_rad = 0.4, .offset = 1.0, .start_s = 0.1}},
      {"double_step", sig::DoubleStep{.amplitude = 8.0, .start_s = 0.2, .second_amplitude = -3.0,
                                      .second_start_s = 1.3, .rise_s = 0.3, .rise_shape = RiseShape::s_curve}},
      {"stacked_steps", sig::StackedSteps{.levels = {1.0, 3.0, -2.0}, .dwell_s = 0.7, .start_s = 0.1,
                                          .rise_s = 0.2, .repeat = true}},
      {"parabolic", sig::Parabolic{.acceleration_per_s2 = 6.0, .start_s = 0.4}},
      {"trapezoid_linear", sig::Trapezoid{.amplitude = 5.0, .start_s = 0.2, .rise_s = 0.3, .hold_s = 0.8, .fall_s = 0.5}},
      {"trapezoid_scurve", sig::Trapezoid{.amplitude = -4.0, .start_s = 0.5, .rise_s = 0.4, .hold_s = 0.3,
                                          .fall_s = 0.6, .rise_shape = RiseShape::s_curve}},
      {"pulse", sig::Trapezoid{.amplitude = 2.0, .start_s = 1.0, .rise_s = 0.0, .hold_s = 0.5, .fall_s = 0.0}},
      {"prbs", sig::Prbs{.order = 5, .bit_period_s = 0.05, .amplitude = 2.0, .offset = 1.0, .seed = 7, .start_s = 0.12}},
  };
  ASSERT_EQ(table.columns.size(), cases.size() + 1);
  for (const auto& [name, signal] : cases) {
    const auto y = sig::sample(signal, 500.0, 3.0);
    const auto& t = table.column("time_s");
    for (std::size_t i = 0; i < t.size(); i += 50) ASSERT_EQ(y.time_s(i), t[i]);
    expect_column(y, table.column(name), 1e-12, name);
  }
}

TEST(Golden, PrbsBitsMatchScipyMaxLenSeq) {
  const auto table = cs::io::read_table(cs::testing::golden_path("signal_prbs_bits.csv"));
  const auto& order = table.column("order");
  const auto& seed = table.column("seed");
  const auto& index = table.column("index");
  const auto& bit = table.column("bit");
  std::size_t row = 0, cases = 0;
  while (row < table.rows()) {
    const int n = static_cast<int>(order[row]);
    const auto s = static_cast<std::uint32_t>(seed[row]);
    std::size_t end = row;
    while (end < table.rows() && order[end] == order[row] && seed[end] == seed[row]) ++end;
    const auto ours = sig::prbs_bits(n, s, end - row);
    for (std::size_t i = row; i < end; ++i) {
      ASSERT_EQ(static_cast<std::size_t>(index[i]), i - row);
      ASSERT_EQ(static_cast<double>(ours[i - row]), bit[i]) << "order " << n << " seed " << s << " bit " << i - row;
    }
    row = end;
    ++cases;
  }
  EXPECT_EQ(cases, 32u);  // orders 2 … 31 plus two extra seeds
}

namespace {
void check_path(const std::string& file, const sig::Signal& command_deg, double rate_hz,
                double duration_s, const sig::PulseTrainConfig& config, std::size_t saturated) {
  const auto table = cs::io::read_table(cs::testing::golden_path(file));
  const auto command = sig::sample(command_deg, rate_hz, duration_s);
  expect_column(command, table.column("command_deg"), 1e-12, file + " command");
  const auto r = sig::apply_position_path(to_rad(command), config);
  cs::UniformSeries commanded_deg = r.commanded_rad;
  for (double& v : commanded_deg.values) v = cs::rad_to_deg(v);
  expect_column(commanded_deg, table.column("commanded_deg"), 1e-11, file + " commanded");
  expect_column(r.pulse_frequency_hz, table.column("pulse_frequency_hz"), 0.0, file + " frequency");
  EXPECT_EQ(r.saturated_updates, saturated) << file;
}
}  // namespace

TEST(Golden, PositionPathStep) {
  check_path("signal_path_step.csv", sig::Step{.amplitude = 10.0, .start_s = 0.1}, 1000.0, 1.0, {}, 0);
}

TEST(Golden, PositionPathSCurve) {
  check_path("signal_path_scurve.csv",
             sig::Step{.amplitude = 56.0, .start_s = 0.2, .rise_s = 0.5, .rise_shape = RiseShape::s_curve},
             1000.0, 1.5, {}, 0);
}

TEST(Golden, PositionPathSampledVelocity) {
  check_path("signal_path_sampled.csv",
             sig::DoubleStep{.amplitude = 8.0, .start_s = 0.1, .second_amplitude = 8.0, .second_start_s = 0.6, .rise_s = 0.1},
             1000.0, 1.2, {.velocity_hold = sig::VelocityHold::sampled}, 0);
}

TEST(Golden, PositionPathSaturated) {
  check_path("signal_path_saturated.csv", sig::Step{.amplitude = 90.0, .start_s = 0.05}, 1000.0, 0.5,
             {.gear_ratio = 0.02}, 2);
}

TEST(Golden, PositionPathReverse) {
  check_path("signal_path_reverse.csv",
             sig::Trapezoid{.amplitude = 20.0, .start_s = 0.1, .rise_s = 0.2, .hold_s = 0.2, .fall_s = 0.3},
             800.0, 1.5, {.update_rate_hz = 25.0, .counts_per_rev = 2500.0, .gear_ratio = 2.0}, 0);
}

TEST(Golden, SpeedPathDaq) {
  const auto table = cs::io::read_table(cs::testing::golden_path("signal_daq.csv"));
  const auto command = sig::sample(sig::Sine{.amplitude = 1500.0, .frequency_hz = 2.0}, 1000.0, 1.0);
  expect_column(command, table.column("command_deg_s"), 1e-12, "daq command");
  const auto r = sig::apply_speed_path(command, {.volts_per_unit = 0.008});
  expect_column(r.volts, table.column("daq_v"), 1e-12, "daq volts");
  EXPECT_EQ(r.clipped_samples, 372u);  // printed by gen_signal.py
}
