#pragma once
// Jerk-limited point-to-point moves (issue 24 item 4; docs/arm.md §7). One axis: the
// minimum-time rest-to-rest "double S" profile under velocity, acceleration and jerk limits —
// seven segments of constant jerk +j, 0, −j, 0, −j, 0, +j (Biagiotti & Melchiorri, Trajectory
// Planning for Automatic Machines and Robots, 2008, §3.4). rise.hpp's S-curve is its special
// case without constant-acceleration and cruise phases (fixed duration, no limits). Several axes:
// each axis's minimum-time profile, the slowest axis sets the duration T, and every other axis
// is time-scaled to T (t → t·T_i/T), which scales its velocity by T_i/T, acceleration by
// (T_i/T)² and jerk by (T_i/T)³, so it stays within its limits and all axes start and end
// together at rest. A profile is an immutable design; at() is noexcept and allocation-free.
#include <span>
#include <string_view>
#include <vector>

#include "clearshape/core/series.hpp"

namespace clearshape::signal {

/// Limits of one axis (magnitudes, in the axis's units per s, s², s³).
struct AxisLimits {
  double velocity = 1.0;
  double acceleration = 1.0;
  double jerk = 1.0;
  /// Throws InvalidArgument naming `owner`.field and the allowed range (finite, > 0).
  void validate(std::string_view owner) const;
};

/// Position, velocity, acceleration and jerk of an axis at one instant.
struct AxisState {
  double position = 0.0;
  double velocity = 0.0;
  double acceleration = 0.0;
  double jerk = 0.0;
};

class JerkLimitedProfile {
 public:
  /// The minimum-time rest-to-rest move from `start` to `end` within `limits` (closed form of
  /// Biagiotti & Melchiorri 2008, §3.4, with v0 = v1 = 0). start == end: duration 0.
  /// Throws InvalidArgument for non-finite positions or invalid limits.
  static JerkLimitedProfile minimum_time(double start, double end, const AxisLimits& limits);
  /// The same path played over `duration_s` >= duration_s() (time scaling; 0 keeps a
  /// zero-length move still). Throws InvalidArgument for a shorter or non-finite duration.
  JerkLimitedProfile time_scaled(double duration_s) const;

  double duration_s() const noexcept { return duration_s_; }
  double start() const noexcept { return start_; }
  double end() const noexcept { return end_; }
  /// Segment durations of the unscaled (minimum-time) profile: jerk phase Tj, acceleration
  /// phase Ta (3 segments), cruise Tv; its duration is 2·Ta + Tv.
  double jerk_time_s() const noexcept { return jerk_time_s_; }
  double acceleration_time_s() const noexcept { return acceleration_time_s_; }
  double cruise_time_s() const noexcept { return cruise_time_s_; }
  /// Largest |velocity| and |acceleration| reached (after time scaling).
  double peak_velocity() const noexcept;
  double peak_acceleration() const noexcept;
  /// The state at `t_s` (start before 0, exactly `end()` at rest from duration_s() on).
  AxisState at(double t_s) const noexcept;

 private:
  AxisState nominal_first_half(double tau_s) const noexcept;
  double start_ = 0.0;
  double end_ = 0.0;
  double distance_ = 0.0;   // |end − start|
  double direction_ = 1.0;  // sign(end − start)
  double jerk_ = 0.0;       // the unscaled profile's jerk magnitude
  double jerk_time_s_ = 0.0;
  double acceleration_time_s_ = 0.0;
  double cruise_time_s_ = 0.0;
  double time_scale_ = 1.0;  // T_min / T: the scaled profile is p(time_scale · t)
  double duration_s_ = 0.0;
};

/// Axes moving together: every axis starts at 0 and ends at duration_s() at rest.
struct SynchronizedMove {
  std::vector<JerkLimitedProfile> axes;
  double duration_s = 0.0;
  /// The slowest axis (the one whose minimum time is duration_s); 0 for no motion.
  std::size_t limiting_axis = 0;
};

/// Synchronised minimum-time move of N axes from `start` to `end` (one limit per axis).
/// Throws InvalidArgument naming axis[i] for mismatched sizes, no axes, non-finite positions
/// or invalid limits.
SynchronizedMove synchronized_move(std::span<const double> start, std::span<const double> end,
                                   std::span<const AxisLimits> limits);

/// One axis sampled at k·sample_time_s for k = 0 … max(1, ceil(duration/sample_time)) (the last
/// sample at or after the end, at rest; a move without motion gives two samples at rest).
struct SampledAxis {
  UniformSeries position;
  UniformSeries velocity;
  UniformSeries acceleration;
};
/// Samples every axis of `move` on the same grid (`sample_time_s` > 0, at most 1e7 samples).
std::vector<SampledAxis> sample_move(const SynchronizedMove& move, double sample_time_s);

}  // namespace clearshape::signal
