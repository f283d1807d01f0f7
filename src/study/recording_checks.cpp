// The unit checks of a recording (recording_checks.hpp, docs/recordings.md).
#include "recording_checks.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::study::detail {

namespace {

constexpr double kDegPerRad = 180.0 / kPi;

bool near_ratio(double value, double target, double rel) { return std::abs(value / target - 1.0) < rel; }

double range_of(const std::vector<double>& v, std::size_t n) {
  n = std::min(n, v.size());
  if (n == 0) return 0.0;
  const auto [lo, hi] = std::minmax_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(n));
  return *hi - *lo;
}

// The likely fix when the link travels ~57.3× (too_large) or ~1/57.3× the motor: the column
// whose declared unit can be the wrong one of deg/rad, and the key to change.
struct Fix {
  std::string column;
  std::string hint;
};

Fix deg_rad_fix(const RecordingColumns& c, bool link_too_large) {
  if (link_too_large) {
    if (c.link_rate_unit == "rad/s") {
      return {c.link_rate, "declared rad/s, looks like deg/s: set link_rate_unit = \"deg/s\""};
    }
    if (c.motor_angle_unit == "deg") {
      return {c.motor_angle, "declared deg, looks like rad: set motor_angle_unit = \"rad\""};
    }
  } else {
    if (c.link_rate_unit == "deg/s") {
      return {c.link_rate, "declared deg/s, looks like rad/s: set link_rate_unit = \"rad/s\""};
    }
    if (c.motor_angle_unit == "rad") {
      return {c.motor_angle, "declared rad, looks like deg: set motor_angle_unit = \"deg\""};
    }
  }
  return {c.link_rate, fmt::format("a factor of 57.3 is degrees against radians: check link_rate_unit (\"{}\"{}) "
                                   "and motor_angle_unit (\"{}\"{})",
                                   c.link_rate_unit,
                                   c.link_rate_unit == "lsb" ? fmt::format(", lsb_per_deg_s = {}", c.lsb_per_deg_s)
                                                             : std::string(),
                                   c.motor_angle_unit,
                                   c.motor_angle_unit == "counts"
                                       ? fmt::format(", counts_per_rev = {}", c.counts_per_rev)
                                       : std::string())};
}

Fix general_fix(const RecordingColumns& c) {
  if (c.link_rate_unit == "lsb") {
    return {c.link_rate, fmt::format("check lsb_per_deg_s (= {}; the ITG-3205 gives 14.375 LSB per °/s)",
                                     c.lsb_per_deg_s)};
  }
  if (c.motor_angle_unit == "counts") {
    return {c.motor_angle, fmt::format("check counts_per_rev (= {})", c.counts_per_rev)};
  }
  return {c.link_rate, fmt::format("check that '{}' is the link's gyroscope rate of this axis in {} and '{}' the "
                                   "motor angle in {} (a gyro offset that changes after the command starts "
                                   "integrates to travel)",
                                   c.link_rate, c.link_rate_unit, c.motor_angle, c.motor_angle_unit)};
}

}  // namespace

void check_time_spacing(const io::Table& t, const std::string& time, const std::string& time_unit, double step_s,
                        double want_s, const std::string& protocol_name, double sample_rate_hz) {
  if (std::abs(step_s - want_s) <= 1e-3 * want_s) return;
  const double ratio = step_s / want_s;
  std::string hint;
  if (time_unit == "s" && near_ratio(ratio, 1000.0, 1e-3)) {
    hint = fmt::format("declared s, looks like ms: set time_unit = \"ms\" for '{}' in the manifest (or divide the "
                       "column by 1000)", time);
  } else if (time_unit == "ms" && near_ratio(ratio, 1e-3, 1e-3)) {
    hint = fmt::format("declared ms, looks like s: set time_unit = \"s\" for '{}' in the manifest", time);
  } else if (time_unit == "s" && near_ratio(ratio, 1e6, 1e-3)) {
    hint = fmt::format("declared s, looks like µs: divide '{}' by 1e6", time);
  } else {
    hint = "resample the recording or set the protocol's sample_rate_hz";
  }
  throw InputError(t.source, 0, time,
                   fmt::format("samples every {:g} {} ({:g} s); the protocol '{}' samples every {:g} s ({:g} Hz) — {}",
                               time_unit == "ms" ? step_s * 1e3 : step_s, time_unit, step_s, protocol_name, want_s,
                               sample_rate_hz, hint));
}

void check_gyro_full_scale(const io::Table& t, const RecordingColumns& c, const std::vector<double>& deg_s,
                           std::size_t n) {
  const double fs = c.gyro_full_scale_deg_s;
  for (std::size_t k = 0; k < std::min(n, deg_s.size()); ++k) {
    if (std::abs(deg_s[k]) <= fs) continue;
    std::string hint;
    if (c.link_rate_unit == "rad/s" && std::abs(deg_s[k]) / kDegPerRad <= fs) {
      hint = "declared rad/s, looks like deg/s: set link_rate_unit = \"deg/s\"";
    } else if (c.link_rate_unit == "lsb") {
      hint = fmt::format("check lsb_per_deg_s (= {}; the ITG-3205 gives 14.375 LSB per °/s)", c.lsb_per_deg_s);
    } else {
      hint = "a gyroscope cannot report a rate beyond its full scale: check link_rate_unit, or set "
             "gyro_full_scale_deg_s to your gyroscope's range";
    }
    throw InputError(t.source, t.line_of_row(k), c.link_rate,
                     fmt::format("link rate {:g} deg/s (read {:g} {}) is beyond the gyroscope's full scale; allowed: "
                                 "within ±{:g} deg/s (gyro_full_scale_deg_s) — {}",
                                 deg_s[k], t.column(c.link_rate)[k], c.link_rate_unit, fs, hint));
  }
}

void check_link_travel(const std::string& file, const RecordingColumns& c, const std::vector<double>& command,
                       const std::vector<double>& motor_deg, const std::vector<double>& link_deg_s,
                       double sample_time_s, std::size_t n) {
  n = std::min({n, command.size(), motor_deg.size(), link_deg_s.size()});
  if (n < 2) return;
  // The gyro's zero-rate offset, as the study removes it (measures.hpp): the mean rate at rest,
  // here the samples before the command first moves (all of them on a rest trial).
  std::size_t rest = 0;
  while (rest < n && std::abs(command[rest] - command[0]) <= 1e-9 * std::max(1.0, std::abs(command[0]))) ++rest;
  double bias = 0.0;
  if (rest >= kTravelBiasMinSamples) {
    for (std::size_t k = 0; k < rest; ++k) bias += link_deg_s[k];
    bias /= static_cast<double>(rest);
  }
  std::vector<double> link_deg(n, 0.0);
  for (std::size_t k = 1; k < n; ++k) {
    link_deg[k] = link_deg[k - 1] + 0.5 * ((link_deg_s[k - 1] - bias) + (link_deg_s[k] - bias)) * sample_time_s;
  }
  const double link = range_of(link_deg, n);
  const double motor = range_of(motor_deg, n);
  const double allowed = kTravelAllowanceDeg + kTravelAllowanceRelative * motor;
  const double ratio = motor > 0.0 ? link / motor : 0.0;
  Fix fix;
  const bool travels = std::max(link, motor) >= kTravelRatioMinDeg;
  if (travels && near_ratio(ratio, kDegPerRad, 0.2)) {
    fix = deg_rad_fix(c, true);
  } else if (travels && near_ratio(ratio, 1.0 / kDegPerRad, 0.2)) {
    fix = deg_rad_fix(c, false);
  } else if (travels && c.link_rate_unit == "deg/s" && near_ratio(ratio, c.lsb_per_deg_s, 0.2)) {
    fix = {c.link_rate, fmt::format("declared deg/s, looks like the gyro's raw words ({} LSB per °/s): set "
                                    "link_rate_unit = \"lsb\"", c.lsb_per_deg_s)};
  } else if (travels && c.link_rate_unit == "lsb" && near_ratio(ratio, 1.0 / c.lsb_per_deg_s, 0.2)) {
    fix = {c.link_rate, "declared lsb, looks like deg/s: set link_rate_unit = \"deg/s\""};
  } else if (std::abs(link - motor) > allowed) {
    fix = general_fix(c);
  } else {
    return;
  }
  throw InputError(file, 0, fix.column,
                   fmt::format("the link travels {:.4g}° ('{}' integrated over {:g} s, its rest offset {:.3g} deg/s "
                               "removed) and the motor {:.4g}° ('{}'), ratio {:.4g}; allowed: within {:g}° + {:g} % "
                               "of the motor's travel, and no deg/rad factor 57.3 — {}",
                               link, c.link_rate, static_cast<double>(n - 1) * sample_time_s, bias, motor,
                               c.motor_angle, ratio, kTravelAllowanceDeg, kTravelAllowanceRelative * 100.0, fix.hint));
}

}  // namespace clearshape::study::detail
