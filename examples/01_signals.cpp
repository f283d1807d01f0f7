// The thesis's command signals and the position-mode command path (§3.2, §4.1.2): a 10° step
// reaches the driver as a ramp over one 30 Hz update, in whole encoder counts. Writes
// signals.csv and exits non-zero if the path does not land on the step to within half a count.
#include <cmath>
#include <cstdio>

#include "clearshape/core/units.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/signal/parameters.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/prbs.hpp"
#include "clearshape/signal/signal.hpp"

namespace cs = clearshape;
namespace sig = clearshape::signal;

int main() {
  const double rate_hz = 1000.0, duration_s = 2.0;
  // Position-mode inputs of §5.2.1 (degrees) and a speed-mode PRBS (°/s), from names + parameters.
  const sig::Signal step = sig::Step{.amplitude = 10.0, .start_s = 0.2};
  const sig::Signal s_curve = sig::Step{.amplitude = 56.0, .start_s = 0.2, .rise_s = 0.8,
                                        .rise_shape = sig::RiseShape::s_curve};
  const sig::Signal double_step = sig::make_signal(
      "double-step", {{"amplitude", 8.0}, {"start_s", 0.2}, {"second_amplitude", 8.0},
                      {"second_start_s", 1.0}, {"rise_s", 0.1}});
  const sig::Signal prbs = sig::Prbs{.order = 7, .bit_period_s = 0.05, .amplitude = 50.0};

  cs::UniformSeries command = sig::sample(step, rate_hz, duration_s);
  cs::UniformSeries command_rad = command;
  for (double& v : command_rad.values) v = cs::deg_to_rad(v);
  const sig::PositionPathResult path = sig::apply_position_path(command_rad, {}, 0.0);

  std::vector<double> commanded_deg = path.commanded_rad.values;
  for (double& v : commanded_deg) v = cs::rad_to_deg(v);
  const std::vector<double> time = command.times_s();
  const std::vector<double> c2 = sig::sample(s_curve, rate_hz, duration_s).values;
  const std::vector<double> c3 = sig::sample(double_step, rate_hz, duration_s).values;
  const std::vector<double> c4 = sig::sample(prbs, rate_hz, duration_s).values;
  cs::io::write_csv("signals.csv",
                    {"time_s", "step_deg", "commanded_deg", "pulse_frequency_hz", "s_curve_deg",
                     "double_step_deg", "prbs_deg_s"},
                    {&time, &command.values, &commanded_deg, &path.pulse_frequency_hz.values, &c2, &c3, &c4});

  long long pulses = 0;
  int moving_updates = 0;
  for (auto n : path.pulses_per_update) {
    pulses += n;
    moving_updates += n != 0 ? 1 : 0;
  }
  const double half_count_deg = 0.5 * 360.0 / 3000.0;
  const double error_deg = std::abs(commanded_deg.back() - 10.0);
  std::printf("10 deg step -> %lld pulses in %d update(s) of 1/30 s, final %.4f deg (error %.4f deg)\n",
              pulses, moving_updates, commanded_deg.back(), error_deg);
  std::printf("PRBS order 7: period %llu bits, taps %zu\n",
              static_cast<unsigned long long>(sig::prbs_period(7)), sig::prbs_taps(7).size());
  return error_deg <= half_count_deg && path.saturated_updates == 0 ? 0 : 1;
}
