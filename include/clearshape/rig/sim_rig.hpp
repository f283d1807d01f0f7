#pragma once
// The simulated rig: the plant (drive + link with clearance, integrated by CVODE tick by tick),
// the drive command path (position: 30 Hz pulse train; speed: 12-bit D/A), the sensors (motor
// encoder, link gyroscope) and seeded noise, behind the Rig interface. Its parameters — the
// "true" rig — are hidden: an experiment can configure only what it could choose on a real
// rig (mode, sample rate, pacing, seed) and must identify the rest from measurements.
// The built-in truth is the thesis rig (truth.hpp documents it; calibration and tests may
// construct a SimRig with an explicit truth through make_sim_rig_with_truth()).
//
// Timing: read() k returns the sample at t = k·T. Between reads the plant integrates with the
// command of the last write() held (zero-order hold at the sample rate). Position mode adds the
// pulse generator's latency: a target written now is programmed at the next 30 Hz update.
// With Pacing::wall_clock, read() k also waits for wall time start + k·T (Pacer); a late
// sample carries MeasurementFlag::overrun and is counted.
#include <cstdint>
#include <memory>

#include "clearshape/rig/pacer.hpp"
#include "clearshape/rig/rig.hpp"

namespace clearshape::rig {

struct RigTruth;

enum class Pacing : std::uint8_t {
  as_fast_as_possible,
  wall_clock,
};

struct SimRigOptions {
  CommandMode mode = CommandMode::position;
  double sample_rate_hz = 1000.0;  ///< read() rate, (0, 100 kHz]
  Pacing pacing = Pacing::as_fast_as_possible;
  std::uint64_t seed = 1;          ///< gyroscope noise and the initial link position in the play
  /// Throws InvalidArgument naming the field.
  void validate() const;
};

class SimRig final : public Rig {
 public:
  /// The thesis rig (built-in truth). Validation and allocation happen in configure().
  explicit SimRig(const SimRigOptions& options);
  ~SimRig() override;

  double sample_time_s() const noexcept override;
  CommandMode mode() const noexcept override { return options_.mode; }
  std::string_view name() const noexcept override { return "sim"; }
  const SimRigOptions& options() const noexcept { return options_; }
  /// Pacing statistics (cycles, overruns, missed periods) of the current activation.
  const PacerStats& pacing_stats() const noexcept;
  /// Contact events (onsets, impacts, …) since activation: a count, not their details.
  std::uint64_t contact_events() const noexcept;

 protected:
  void on_configure() override;
  void on_activate() override;
  void on_deactivate() noexcept override;
  void on_cleanup() noexcept override;
  Status on_read(Measurement& measurement) noexcept override;
  Status on_write(const Command& command) noexcept override;

 private:
  friend std::unique_ptr<SimRig> make_sim_rig_with_truth(const SimRigOptions&, const RigTruth&);
  SimRig(const SimRigOptions& options, const RigTruth& truth);

  struct Impl;
  SimRigOptions options_;
  std::unique_ptr<Impl> impl_;
};

/// Calibration and test path: a SimRig with an explicit truth (declared here so that the
/// experiment-facing API has no way to pass or read one; include truth.hpp to build a truth).
std::unique_ptr<SimRig> make_sim_rig_with_truth(const SimRigOptions& options,
                                                const RigTruth& truth);

}  // namespace clearshape::rig
