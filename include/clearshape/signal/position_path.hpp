#pragma once
// Position-mode drive command path (thesis §3.2, §4.1.2): the position trajectory becomes a
// velocity profile, the velocity is held for each update period of the pulse generator (the
// driver detects frequency changes at 30 Hz), and the quadrature A/B pulse train — at most
// 500 kHz — carries whole counts to the driver, which integrates them into the position it
// actually receives. For an ideal step that position is "a higher sloped ramp" (§4.1.2).
//
// Counts: `counts_per_rev` command pulses (full A/B cycles) turn the motor once at gear ratio 1
// (§4.1.2: "3000 pulses are required to achieve a full rotation", Table 3.1 encoder 3000 P/R);
// a ×4 decoder sees 4 edges per pulse. `gear_ratio` is the driver's electronic gear (motor counts
// per command pulse). Each update period carries a whole number of pulses at constant frequency,
// so the commanded position is a whole count at every update instant.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/core/status.hpp"

namespace clearshape::signal {

/// How the velocity held over update period k, [t_k, t_k + T), is taken from the trajectory p(t).
enum class VelocityHold {
  /// (p(t_k + T) − p(t_k)) / T (p(t_0) = the initial position), and the pulses aim at p(t_k + T): the commanded position meets
  /// the trajectory (to a whole count) at every update instant; an ideal step becomes a ramp of
  /// slope amplitude/T. Needs the trajectory one period ahead (it is generated beforehand, as
  /// in the thesis). Default.
  lookahead,
  /// dp/dt at t_k (backward difference at the input sample time) held for T; the pulses aim at
  /// the integral of the held velocity. The literal reading of §3.2; misses short moves.
  sampled,
};

struct PulseTrainConfig {
  double update_rate_hz = 30.0;             ///< velocity updates per second (§3.2: 30 Hz)
  double counts_per_rev = 3000.0;           ///< command pulses per motor revolution (Table 3.1)
  double gear_ratio = 1.0;                  ///< electronic gear: motor counts per command pulse
  double max_pulse_frequency_hz = 500e3;    ///< pulse input limit of the driver (§3.2)
  VelocityHold velocity_hold = VelocityHold::lookahead;

  /// Throws InvalidArgument naming the field (update rate in (0, 10 kHz], counts per rev and
  /// gear ratio > 0, at least one pulse per update at the maximum frequency).
  void validate() const;
  double update_period_s() const noexcept { return 1.0 / update_rate_hz; }
  /// Command pulses per motor radian: counts_per_rev / (gear_ratio · 2π).
  double counts_per_rad() const noexcept;
  /// Largest number of pulses one update period can carry: floor(max frequency · period).
  std::int64_t max_counts_per_update() const noexcept;
};

/// The pulse generator's run-time state (design/state split). Per update period call program()
/// once, then query the commanded position at any time inside the period. noexcept and
/// allocation-free after construction.
class PulseTrain {
 public:
  /// Validates `config`; starts at count 0.
  explicit PulseTrain(const PulseTrainConfig& config);

  /// Sets the count to round(position_rad · counts_per_rad) with no pulses in flight.
  void reset(double position_rad) noexcept;
  /// Starts a new update period: the pulses of the previous one are complete; this one carries
  /// round(target · counts_per_rad) − count pulses, capped at max_counts_per_update(). Returns
  /// Status::out_of_range when the cap bound (the commanded position lags), Status::not_finite
  /// (and no pulses) for a non-finite target, otherwise Status::ok.
  Status program(double target_rad) noexcept;

  /// Whole counts received `elapsed_s` into the current period (elapsed clamped to [0, T]).
  std::int64_t count_at(double elapsed_s) const noexcept;
  double commanded_rad(double elapsed_s) const noexcept;
  /// Count at the start of the current period.
  std::int64_t count() const noexcept { return count_; }
  /// Signed pulses of the current period (negative = reverse).
  std::int64_t pulses() const noexcept { return pulses_; }
  /// Signed pulse frequency of the current period: pulses / T.
  double pulse_frequency_hz() const noexcept;
  const PulseTrainConfig& config() const noexcept { return config_; }

 private:
  PulseTrainConfig config_;
  double counts_per_rad_;
  std::int64_t max_counts_;
  std::int64_t count_ = 0;
  std::int64_t pulses_ = 0;
};

struct PositionPathResult {
  UniformSeries commanded_rad;       ///< position the driver receives, at the input sample times
  UniformSeries pulse_frequency_hz;  ///< signed pulse frequency, at the input sample times
  UniformSeries held_velocity_rad_s; ///< velocity profile held per update period (before counts and cap)
  std::vector<std::int64_t> pulses_per_update;  ///< signed pulses of each update period
  std::int64_t initial_count = 0;    ///< count before the first period
  double counts_per_rad = 0.0;
  std::size_t saturated_updates = 0; ///< update periods whose pulses the frequency cap reduced
  double max_lag_rad = 0.0;          ///< largest |aimed − commanded| position at an update instant

  double update_period_s() const noexcept { return held_velocity_rad_s.sample_time_s; }
  double update_start_s() const noexcept { return held_velocity_rad_s.start_s; }
};

/// The position-mode path as a real-time loop runs it (the rig's firmware and rig::SimRig): at
/// the first sample tick at or after each update instant t_k = latency + k·T the command written
/// at that tick becomes the target, and the pulses reach it by t_{k+1}; returns, per sample, the
/// commanded angle the drive holds over that sample (rad). Unlike apply_position_path (the
/// trajectory known beforehand: each update aims one period ahead), nothing is looked ahead: a
/// move reaches the drive about one update later, at the ticks the loop's clock gives it.
/// `latency_s` in [0, T). Throws InvalidArgument for an empty or non-finite input or config.
UniformSeries apply_realtime_position_path(const UniformSeries& position_rad, const PulseTrainConfig& config,
                                           double latency_s = 0.0);

/// Runs the position-mode path over a trajectory sampled uniformly (linear interpolation
/// between samples, held after the end). Update instants are t_k = start + k·T for every
/// t_k <= the last sample time. The driver starts at `initial_rad` (default: the first sample;
/// give the value before the signal starts, e.g. 0, so that a step at t = 0 is a move).
/// Throws InvalidArgument for an empty or non-finite input or an invalid config.
PositionPathResult apply_position_path(const UniformSeries& position_rad,
                                       const PulseTrainConfig& config,
                                       std::optional<double> initial_rad = std::nullopt);

}  // namespace clearshape::signal
