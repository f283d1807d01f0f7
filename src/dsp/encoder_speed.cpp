#include "clearshape/dsp/encoder_speed.hpp"

#include <algorithm>
#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/butterworth.hpp"

namespace clearshape::dsp {

SosDesign thesis_speed_filter(double sample_time_s) {
  require_positive("sample_time_s", sample_time_s);
  // §3.3: 4th-order low-pass Butterworth, passband edge 30 rad/s.
  return butter_lowpass_rad_s(kThesisSpeedFilterOrder, kThesisSpeedFilterCutoffRadS,
                              1.0 / sample_time_s);
}

std::vector<double> encoder_counts_to_deg(std::span<const std::int64_t> counts,
                                          double counts_per_rev) {
  require_positive("counts_per_rev", counts_per_rev);
  const double deg_per_count = 360.0 / counts_per_rev;
  std::vector<double> out(counts.size());
  for (std::size_t i = 0; i < counts.size(); ++i) out[i] = static_cast<double>(counts[i]) * deg_per_count;
  return out;
}

std::vector<double> angle_speed_deg_s(std::span<const double> angle_deg, double sample_time_s,
                                      Phase phase) {
  const SosDesign filter = thesis_speed_filter(sample_time_s);
  if (phase == Phase::causal) {
    return sosfilt(filter, backward_difference(angle_deg, sample_time_s));  // real-time chain
  }
  // Offline chain: central difference + forward-backward filtering with a long odd pad.
  const auto pad = static_cast<std::size_t>(std::lround(kThesisZeroPhasePadS / sample_time_s));
  const std::size_t n = angle_deg.size();
  FiltfiltOptions options;
  options.pad_length = std::min(pad, n > 0 ? n - 1 : 0);
  return sosfiltfilt(filter, central_difference(angle_deg, sample_time_s), options);
}

std::vector<double> encoder_speed_deg_s(std::span<const std::int64_t> counts, double sample_time_s,
                                        Phase phase, double counts_per_rev) {
  return angle_speed_deg_s(encoder_counts_to_deg(counts, counts_per_rev), sample_time_s, phase);
}

StreamingEncoderSpeed::StreamingEncoderSpeed(double sample_time_s, double counts_per_rev)
    : deg_per_count_(360.0 / counts_per_rev),
      difference_(sample_time_s),
      filter_(thesis_speed_filter(sample_time_s)) {
  require_positive("counts_per_rev", counts_per_rev);
}

double StreamingEncoderSpeed::step(std::int64_t count) noexcept {
  return filter_.step(difference_.step(static_cast<double>(count) * deg_per_count_));
}

void StreamingEncoderSpeed::reset() noexcept {
  difference_.reset();
  filter_.reset();
}

}  // namespace clearshape::dsp
