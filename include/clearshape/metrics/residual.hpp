#pragma once
// Residual vibration left after a move, and the delay a shaper adds to it.
#include <cstddef>
#include <optional>

#include "clearshape/core/series.hpp"

namespace clearshape::metrics {

/// Mean of the last `fraction` (0, 1] of the samples (at least one): the "final value" of a
/// response whose last sample is noisy.
double final_value(const UniformSeries& response, double fraction = 0.1);

struct ResidualVibration {
  double peak_to_peak = 0.0;       ///< max − min of y for t >= after_s
  double rms_about_final = 0.0;    ///< sqrt(mean((y − y_final)²)) for t >= after_s
  double max_abs_deviation = 0.0;  ///< max |y − y_final| for t >= after_s
  double final_value = 0.0;        ///< y_final used
  std::size_t samples = 0;
};

/// Residual vibration of `response` from `after_s` on, about `final` (default:
/// final_value(response)). Throws InvalidArgument when no sample lies at or after `after_s`.
ResidualVibration residual_vibration(const UniformSeries& response, double after_s,
                                     std::optional<double> final = std::nullopt);

/// First time y reaches initial + fraction·(final − initial), linearly interpolated; NaN if it
/// never does. `final` defaults to final_value(response).
double time_to_fraction_s(const UniformSeries& response, double fraction = 0.5,
                          double initial = 0.0, std::optional<double> final = std::nullopt);

/// Delay added by shaping: time_to_fraction_s(shaped) − time_to_fraction_s(unshaped), both
/// measured towards the unshaped response's final value (so both reach the same level). NaN if
/// either never reaches it. (The upper bound, the shaper's own length, is Shaper::duration_s().)
double shaping_delay_s(const UniformSeries& unshaped, const UniformSeries& shaped,
                       double fraction = 0.5, double initial = 0.0);

}  // namespace clearshape::metrics
