#pragma once
// Run-to-run variation of the simulated rig (the truth's RunVariation): what makes a real rig's
// repeated runs differ (thesis §4.1, Tables 4.1–4.2, Eq. 4.1; the trial spread of Tables 5.1 and
// B.1–B.5). SimRig draws one RunDraw per activation (configuration time, seeded from
// SimRigOptions::seed and the activation's index) and applies it in the allocation-free read
// path; the analog command noise is drawn per sample there from a pre-seeded generator.
// Every σ defaults to 0 (a rig that repeats exactly but for the initial play and the gyro noise).
#include <random>

namespace clearshape::rig {

struct RunVariation {
  /// Relative σ of the position-mode drive gain Kp per activation (Gaussian, clipped at ±4σ);
  /// the servo's encoder loop holds it small. Range [0, 0.1].
  double position_gain_rel_sigma = 0.0;
  /// Relative σ of the speed-mode drive gain Kp per activation (amplifier and motor-constant
  /// drift with temperature). Range [0, 0.1].
  double speed_gain_rel_sigma = 0.0;
  /// Command start latency, drawn uniformly in [0, start_latency_max_s] per activation: the
  /// acquisition and the command clocks are not locked. Position mode: the phase of the 30 Hz
  /// pulse-update clock is shifted by it; speed mode: every D/A update comes that late (within
  /// one sample). Range [0, 1e-3] s, and at most one sample period.
  double start_latency_max_s = 0.0;
  /// Speed mode: white noise on the D/A output, σ in V per sample. Range [0, 0.1] V.
  double analog_noise_v = 0.0;
  /// Speed mode: D/A output offset, σ in V per activation (Gaussian, clipped at ±4σ).
  /// Range [0, 0.1] V.
  double analog_offset_sigma_v = 0.0;
  /// Relative σ of the flank damping D per activation (lubrication, temperature): D·exp(σ z),
  /// z standard normal clipped at ±4. Range [0, 1].
  double flank_damping_rel_sigma = 0.0;

  bool any() const noexcept {
    return position_gain_rel_sigma > 0.0 || speed_gain_rel_sigma > 0.0 || start_latency_max_s > 0.0 ||
           analog_noise_v > 0.0 || analog_offset_sigma_v > 0.0 || flank_damping_rel_sigma > 0.0;
  }
  /// Throws InvalidArgument naming the field, its value and the allowed range.
  void validate() const;
};

/// The values of one activation.
struct RunDraw {
  double position_gain = 1.0;         ///< factor on the position drive's Kp
  double speed_gain = 1.0;            ///< factor on the speed drive's Kp
  double start_latency_s = 0.0;       ///< command latency (s)
  double analog_offset_v = 0.0;       ///< D/A offset (V)
  double flank_damping_factor = 1.0;  ///< factor on the contact damping D
};

/// Draws one activation's values from `rng` (always the same number of draws, in field order,
/// so a zero σ leaves the others unchanged).
RunDraw draw_run_variation(const RunVariation& variation, std::mt19937_64& rng);

}  // namespace clearshape::rig
