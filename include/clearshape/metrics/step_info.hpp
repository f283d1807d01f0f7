#pragma once
// Step-response characteristics, with the definitions of MATLAB `stepinfo(y, t, yfinal, yinit)`.
// Δ = yfinal − yinit; every time is measured from `step_time_s`; crossing times are linearly
// interpolated between samples.
//   rise time      first time y reaches yinit + 0.9·Δ minus first time it reaches yinit + 0.1·Δ
//   settling time  time after which |y − yfinal| <= threshold·|Δ| holds to the end of the
//                  record (the band-edge crossing after the last sample outside the band)
//   settling min/max  min/max of y from the first time it reaches yinit + 0.9·Δ
//   overshoot %    100·max(0, max((y − yinit)·sgnΔ) − |Δ|) / |Δ|
//   undershoot %   100·max(0, −min((y − yinit)·sgnΔ)) / |Δ|
//   peak, peak time  max |y − yinit| and when it first occurs
// A characteristic that the record does not reach (never rises, never settles) is NaN.
#include <optional>

#include "clearshape/core/series.hpp"

namespace clearshape::metrics {

struct StepInfoOptions {
  std::optional<double> final_value;    ///< yfinal; default: the last sample (as MATLAB)
  double initial_value = 0.0;           ///< yinit (as MATLAB)
  std::optional<double> step_time_s;    ///< default: the first sample time
  double settling_threshold = 0.02;     ///< (0, 1)
  double rise_low = 0.1;                ///< rise-time limits, 0 <= low < high <= 1
  double rise_high = 0.9;
};

struct StepInfo {
  double rise_time_s = 0.0;
  double settling_time_s = 0.0;
  double settling_min = 0.0;
  double settling_max = 0.0;
  double overshoot_percent = 0.0;
  double undershoot_percent = 0.0;
  double peak = 0.0;
  double peak_time_s = 0.0;
  double final_value = 0.0;  ///< the yfinal used
};

/// Throws InvalidArgument for fewer than 2 samples, non-finite samples, yfinal == yinit or
/// options out of range.
StepInfo step_info(const UniformSeries& response, const StepInfoOptions& options = {});

}  // namespace clearshape::metrics
