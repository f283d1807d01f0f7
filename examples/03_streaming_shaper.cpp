// A 1 kHz control loop shapes a step command with a ZVD shaper, one sample per tick, and
// checks the result against offline shaping of the whole command. Exit 1 on a mismatch.
#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/streaming.hpp"

namespace sh = clearshape::shaping;

int main() {
  // ZVD for a 10 Hz, ζ = 0.1 mode (Singer & Seering 1990): [1, 2K, K²]/(1+K)² at [0, Td/2, Td].
  const sh::Mode mode = sh::Mode::from_hz(10.0, 0.1);
  const double zeta = mode.damping_ratio;
  const double k = std::exp(-zeta * std::numbers::pi / std::sqrt(1.0 - zeta * zeta));
  const double half_td_s = std::numbers::pi / mode.damped_frequency_rad_s();
  const sh::Shaper zvd("zvd", {{0.0, 1.0}, {half_td_s, 2.0 * k}, {2.0 * half_td_s, k * k}});

  const double sample_time_s = 1e-3;  // 1 kHz loop
  clearshape::UniformSeries command{0.0, sample_time_s, std::vector<double>(300, 0.0)};
  for (std::size_t i = 50; i < command.size(); ++i) command.values[i] = 10.0;  // 10° step at 50 ms

  sh::StreamingShaper shaper(zvd, sample_time_s, command.values.front());  // allocates here
  std::vector<double> streamed;
  streamed.reserve(command.size());
  for (double u : command.values) {  // the loop body: noexcept, no allocation
    double y = 0.0;
    if (shaper.step(u, y) != clearshape::Status::ok) return 1;
    streamed.push_back(y);
  }

  const clearshape::UniformSeries offline = sh::shape_offline(zvd, command, /*extend=*/false);
  double worst = 0.0;
  for (std::size_t i = 0; i < streamed.size(); ++i) {
    worst = std::fmax(worst, std::fabs(streamed[i] - offline.values[i]));
  }
  std::printf("ZVD: %zu impulses -> %zu taps, history %zu samples, duration %.4f s\n", zvd.size(),
              shaper.tap_count(), shaper.history_samples(), zvd.duration_s());
  std::printf("t_s,command_deg,shaped_deg\n");
  for (std::size_t i = 40; i < streamed.size(); i += 20) {
    std::printf("%.3f,%.1f,%.6f\n", command.time_s(i), command.values[i], streamed[i]);
  }
  std::printf("max |streaming - offline| = %.3g deg\n", worst);
  const bool settled = std::fabs(streamed.back() - 10.0) < 1e-12;  // reached the final value
  if (worst > 1e-12 || !settled) {
    std::fprintf(stderr, "mismatch: streaming and offline shaping disagree or did not settle\n");
    return 1;
  }
  return 0;
}
