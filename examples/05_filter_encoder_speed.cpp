// Thesis §3.3/§4.1.1: the motor speed is measured by differentiating the encoder angle and
// filtering it with a 4th-order, 30 rad/s low-pass Butterworth (1 kHz logging). Here a known
// angle θ(t) = 90°·(1 − cos πt) is quantized like the 3000 p/r encoder decoded ×4 (0.03°/count),
// run through both variants of the chain, and compared with the analytic speed 90π·sin(πt) °/s.
// Exit 1 if an error exceeds its bound.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <vector>

#include "clearshape/core/units.hpp"
#include "clearshape/dsp/encoder_speed.hpp"

namespace dsp = clearshape::dsp;
using clearshape::kPi;

int main() {
  const double dt = dsp::kThesisSampleTimeS;
  const double deg_per_count = 360.0 / dsp::kThesisEncoderCountsPerRev;
  const std::size_t n = 4001;  // two full periods, 4 s
  std::vector<std::int64_t> counts(n);
  std::vector<double> speed(n);  // analytic, °/s
  for (std::size_t i = 0; i < n; ++i) {
    const double t = dt * static_cast<double>(i);
    counts[i] = static_cast<std::int64_t>(std::floor(90.0 * (1.0 - std::cos(kPi * t)) / deg_per_count));
    speed[i] = 90.0 * kPi * std::sin(kPi * t);
  }
  // Raw backward difference: quantization makes steps of 0.03° / 1 ms = 30 °/s.
  const auto raw = dsp::backward_difference(dsp::encoder_counts_to_deg(counts), dt);
  // Offline zero-phase chain vs the analytic speed (no lag; |H(0.5 Hz)|² = 1 − 2e-8).
  const auto zero_phase = dsp::encoder_speed_deg_s(counts, dt, dsp::Phase::zero_phase);
  // Real-time causal chain vs the analytic speed through the same filter: what remains is the
  // quantization noise the filter lets through (the lag itself is the filter's, by design).
  const auto causal = dsp::encoder_speed_deg_s(counts, dt, dsp::Phase::causal);
  const auto speed_filtered = dsp::sosfilt(dsp::thesis_speed_filter(dt), speed);

  double raw_err = 0.0, zero_err = 0.0, causal_err = 0.0, lag_err = 0.0;
  for (std::size_t i = 1; i < n; ++i) {
    raw_err = std::max(raw_err, std::abs(raw[i] - speed[i]));
    zero_err = std::max(zero_err, std::abs(zero_phase[i] - speed[i]));
    causal_err = std::max(causal_err, std::abs(causal[i] - speed_filtered[i]));
    lag_err = std::max(lag_err, std::abs(causal[i] - speed[i]));
  }
  const double peak = 90.0 * kPi;
  std::printf("analytic peak speed               %8.3f deg/s\n", peak);
  std::printf("raw backward difference, max err  %8.3f deg/s\n", raw_err);
  std::printf("zero-phase chain, max err         %8.3f deg/s (bound 0.1)\n", zero_err);
  std::printf("causal chain vs filtered truth    %8.3f deg/s (bound 1.0)\n", causal_err);
  std::printf("causal chain vs truth (filter lag) %7.3f deg/s (information)\n", lag_err);
  const bool ok = zero_err < 0.1 && causal_err < 1.0 && raw_err > 10.0 * zero_err;
  std::printf("%s\n", ok ? "OK" : "FAILED");
  return ok ? 0 : 1;
}
