#pragma once
// What Eq. 5.1 reads when nothing moves, and what a command can therefore show (issue 12).
//
//   measurement floor  Eq. 5.1 on rest trials — a zero command of the record's length, seeded
//                      like every other trial, through the same sensor chain and gyro-bias
//                      removal (md_series) — over the window the input's rig trials used: from the
//                      median of their steady-state starts (Eq. 5.1's k, start_time_s in the rig
//                      table) to the end, M the mean of that window. It is the integrated gyro's
//                      noise and drift over that window: a command that cancelled the residual
//                      vibration completely would read it, not 0. (Eq. 5.1's own start search is
//                      no window on a rest record: with no move to depart from it settles on the
//                      noise's last excursion, seconds late — kept as a diagnostic only.)
//   90 % target        (1 − 90/100) × the unshaped mean MD of the input: the MD a command must
//                      reach for a 90 % improvement (Appendix B: improvement = 1 − with/without).
//   verdict            below-floor  the target is below the floor's mean: no command can show a
//                                   90 % improvement on this rig's sensors;
//                      reached      the best shaped column's mean MD is at or below the target;
//                      reachable    the target lies above the floor but no tested command
//                                   reaches it: the command, not the sensor, is the limit.
#include <limits>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "clearshape/study/protocol.hpp"
#include "clearshape/study/record.hpp"

namespace clearshape::study {

/// The improvement issue 12 asks for (percent of the unshaped mean MD).
inline constexpr double kReachTargetImprovementPercent = 90.0;

/// Eq. 5.1 with its steady state fixed to start at the first sample at or after `start_s`:
/// sqrt(Σ_{i>=k} (M − s_i)² / n), M the mean of those n samples.
double fixed_start_mean_deviation(const UniformSeries& series, double start_s);

/// The floor of each rest trial in trial order: fixed_start_mean_deviation of its md_series.
std::vector<double> floor_mean_deviations(std::span<const Record> rest, const MeasureSpec& measure,
                                          double start_s);

/// The median of a list (the mean of the middle two for an even count); NaN when empty.
double median(std::vector<double> values);

enum class Reach { below_floor, reached, reachable };
std::string_view to_string(Reach reach) noexcept;  ///< "below-floor", "reached", "reachable"

/// The numbers one verdict is computed from (one rig table: its input's unshaped trials, the
/// rest trials in that input's window, the shaped column with the smallest mean MD).
struct ReachNumbers {
  double unshaped_mean = 0.0;
  double unshaped_std = 0.0;
  double floor_mean = 0.0;
  double floor_std = 0.0;
  std::string best_label;  ///< empty: the table has no shaped column
  double best_mean = std::numeric_limits<double>::quiet_NaN();
};

struct ReachVerdict {
  Reach reach = Reach::below_floor;
  double target = 0.0;   ///< (1 − kReachTargetImprovementPercent/100) × unshaped_mean
  /// The improvement a command that left no residual at all would show: 100 (1 − floor/unshaped),
  /// the floor's mean read instead of 0 (NaN when the unshaped mean is not positive).
  double floor_improvement_percent = 0.0;
  std::string sentence;  ///< the verdict with its numbers, for the report
};

/// The verdict of `n`; `unit` ("deg", "deg/s") is written after every number of the sentence.
ReachVerdict reach_verdict(const ReachNumbers& n, std::string_view unit);

}  // namespace clearshape::study
