#pragma once
// What the study computes from a recorded run (thesis §3.3, §4.1, §5.1.2):
//   motor speed   encoder angle → derivative → 4th-order Butterworth, 30 rad/s (dsp chain)
//   link angle    ∫ (gyro rate − bias) dt, trapezoidal, bias = mean rate at rest before the
//                 move (first bias_window_s); starts at 0
//   MD            Eq. 5.1 on the protocol's md_signal, the steady-state start searched after
//                 the start of the input's last move (metrics::mean_deviation)
//   move end      the last time the motor is farther than 2 % of its move from its final value
#include <span>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/record.hpp"

namespace clearshape::study {

/// Encoder speed in °/s through the thesis chain (causal or zero-phase).
std::vector<double> motor_speed_deg_s(const Record& record, bool zero_phase = false);

/// Gyro rate integrated to an angle in ° after removing the bias measured on [0, bias_window_s).
std::vector<double> link_angle_deg(const Record& record, double bias_window_s);

/// The signal Eq. 5.1 is computed on, as a series.
UniformSeries md_series(const Record& record, const MeasureSpec& measure);

/// Eq. 5.1 of a run for an input.
metrics::MeanDeviationResult run_mean_deviation(const Record& record, const MeasureSpec& measure,
                                                const InputSpec& input);

/// Eq. 5.1 of a series whose steady state is searched after `search_from_s`.
metrics::MeanDeviationResult series_mean_deviation(const UniformSeries& series,
                                                   const MeasureSpec& measure, double search_from_s);

/// Time (s) after which |y − y_final| stays within `fraction` of |y_final − y(first)|, searched
/// from `from_s` (y_final = mean of the last 10 %). Returns from_s when y never moves.
double settle_time_s(std::span<const double> y, double sample_time_s, double from_s,
                     double fraction = 0.02);

/// Mean and sample standard deviation (0 for one value) of a list.
struct MeanStd {
  double mean = 0.0;
  double std = 0.0;
};
MeanStd mean_std(std::span<const double> values);

}  // namespace clearshape::study
