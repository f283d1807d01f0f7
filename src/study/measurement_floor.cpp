// The measurement floor of Eq. 5.1 and the reach verdict (study/measurement_floor.hpp).
#include "clearshape/study/measurement_floor.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/study/measures.hpp"

namespace clearshape::study {

double fixed_start_mean_deviation(const UniformSeries& series, double start_s) {
  const auto& s = series.values;
  if (s.empty()) throw InvalidArgument("fixed_start_mean_deviation: empty series");
  const double from = std::ceil((start_s - series.start_s) / series.sample_time_s - 1e-9);
  const std::size_t k = from <= 0.0 ? 0 : std::min(static_cast<std::size_t>(from), s.size() - 1);
  double mean = 0.0;
  for (std::size_t i = k; i < s.size(); ++i) mean += s[i];
  const double n = static_cast<double>(s.size() - k);
  mean /= n;
  double sum_sq = 0.0;
  for (std::size_t i = k; i < s.size(); ++i) sum_sq += (mean - s[i]) * (mean - s[i]);
  return std::sqrt(sum_sq / n);  // Eq. 5.1 with k given
}

std::vector<double> floor_mean_deviations(std::span<const Record> rest, const MeasureSpec& measure, double start_s) {
  std::vector<double> md;
  md.reserve(rest.size());
  for (const Record& r : rest) md.push_back(fixed_start_mean_deviation(md_series(r, measure), start_s));
  return md;
}

double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  std::sort(values.begin(), values.end());
  const std::size_t h = values.size() / 2;
  return values.size() % 2 == 1 ? values[h] : 0.5 * (values[h - 1] + values[h]);
}

std::string_view to_string(Reach reach) noexcept {
  switch (reach) {
    case Reach::below_floor: return "below-floor";
    case Reach::reached: return "reached";
    case Reach::reachable: return "reachable";
  }
  return "below-floor";
}

ReachVerdict reach_verdict(const ReachNumbers& n, std::string_view unit) {
  ReachVerdict v;
  // Appendix B: improvement = (without − with)/without, so 90 % leaves 10 % of the unshaped MD.
  v.target = (100.0 - kReachTargetImprovementPercent) / 100.0 * n.unshaped_mean;
  v.floor_improvement_percent = n.unshaped_mean > 0.0 ? 100.0 * (1.0 - n.floor_mean / n.unshaped_mean)
                                                      : std::numeric_limits<double>::quiet_NaN();
  const bool has_best = !n.best_label.empty() && std::isfinite(n.best_mean);
  const std::string floor = fmt::format("{:.3g} ± {:.2g} {}", n.floor_mean, n.floor_std, unit);
  const std::string target = fmt::format("the {:g} % target {:.3g} {}", kReachTargetImprovementPercent, v.target, unit);
  if (v.target < n.floor_mean) {
    v.reach = Reach::below_floor;
    v.sentence = fmt::format("{} is below the measurement floor {}: no command can show it on this rig's sensors (one "
                             "that left no residual would read the floor, {:.0f} % improvement)",
                             target, floor, v.floor_improvement_percent);
    if (has_best && n.floor_mean > 0.0) {
      v.sentence += fmt::format("; the best design, {}, reads {:.3g} {}, {:.2g}× the floor", n.best_label, n.best_mean,
                                unit, n.best_mean / n.floor_mean);
    }
    return v;
  }
  if (has_best && n.best_mean <= v.target) {
    v.reach = Reach::reached;
    v.sentence = fmt::format("reached: the best design, {}, leaves {:.3g} {}, at or below {} (measurement floor {})",
                             n.best_label, n.best_mean, unit, target, floor);
    return v;
  }
  v.reach = Reach::reachable;
  v.sentence = fmt::format("reachable in principle: {} lies above the measurement floor {}; ", target, floor);
  if (has_best) {
    v.sentence += fmt::format("the best design, {}, leaves {:.3g} {} ({:.2g}× the target): the command, not the "
                              "sensor, is the limit",
                              n.best_label, n.best_mean, unit, v.target > 0.0 ? n.best_mean / v.target : 0.0);
  } else {
    v.sentence += "no shaped command was tested";
  }
  return v;
}

}  // namespace clearshape::study
