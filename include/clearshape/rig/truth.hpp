#pragma once
// The hidden "true" parameters of the simulated rig — the CALIBRATION AND TEST PATH.
//
// Experiments use SimRig (sim_rig.hpp), which is built with the thesis rig below and never
// exposes it: an experiment identifies the rig from its measurements as it would a real one.
// Only calibration (fitting the truth to the thesis's unshaped measurements, docs/design.md §2),
// what-if simulation (`clearshape simulate`) and tests include this header.
//
// The built-in truth, thesis_rig_truth() — the thesis rig CALIBRATED by `clearshape
// calibrate-rig` (docs/design.md §2; study/rig_calibration.hpp; the values and the command that
// reproduces them are in studies/sim-rig-truth.toml). It is the physical prior below with what
// the calibration fitted replaced:
//   speed drive     P3UZ Kp 25.47 (deg/s)/V, Tz 0.1306 s, ζ 0.4682, Tw 0.04164 s, Tp3 0.1540 s:
//                   its response through the thesis's 30 rad/s Butterworth (§3.3) is the
//                   thesis's Eq. 4.2 speed model (the thesis identified drive × filter)
//   play, flank     total play 2β = 0.0320°, thesis law F = K δ + D δ̇ (n = 1, F >= 0),
//                   K = 45.16 N·m/rad, D = 0.1236 N·m·s/rad, both modes
//   gyroscope       rate-noise density 0.0140 °/s/√Hz (DLPF 42 Hz kept)
//   fitted to       the unshaped ("without is") Eq. 5.1 means of Tables B.1–B.5; residuals, ours
//                   vs thesis: B.1 +4.0 %, B.2 +9.8 %, B.3 −1.5 %, B.4 −12.4 %, B.5 −2.4 %
//                   (Table 5.1, speed, not a target: +13.8 %)
//   variation       (variation.hpp) drive-gain σ 8.0e-5 (position) / 2.9e-3 (speed), start
//                   latency uniform in [0, 0.51 ms], D/A noise σ 4.1 mV per sample and offset
//                   σ 1.1 mV per run, flank damping σ(ln D) 0.18 — fitted to the mean Eq. 4.1
//                   errors of Tables 4.1–4.2 and the unshaped trials' spread (5.1, B.1–B.5);
//                   ours/thesis: Table 4.1 ×1.23 ×1.63 ×1.23 ×0.49 (step, ramp, sine, PRBS),
//                   Table 4.2 ×1.58 (step) ×0.06 (double step: not reached), spreads B.1–B.5
//                   ×1.84 ×0.76 ×0.55 ×1.52 ×3.07, Table 5.1 ×0.15 (not reached)
//
// uncalibrated_thesis_rig_prior() — the physical prior the calibration starts from:
//   drive           thesis Eq. 4.2 process models, one per mode (lti presets)
//   play            total backlash 2β = 1.0° (the link turns freely ±0.5° about the shaft)
//   link            J = 5.0e-3 kg·m² (0.2 m bar with the gyroscope and an added mass at the
//                   tip), vertical axis (no gravity torque), ground drag 1e-4 N·m·s/rad
//   contact         thesis law F = K δ^1.5 + D δ̇ clamped at F >= 0, with the thesis's
//                   per-mode values: position K = 1e4 N·m/rad^1.5, D = 300 N·m·s/rad;
//                   speed K = 5 N·m/rad^1.5, D = 350 N·m·s/rad
//   joint friction  viscous 1e-3 N·m·s/rad on the relative rate (lubricated play)
//   encoder         3000 lines ×4 = 12000 counts/rev (0.03°)
//   gyroscope       ITG-3205: 14.375 LSB/(°/s), ±2000 °/s, noise 0.03 °/s/√Hz, DLPF 42 Hz,
//                   no bias, no latency
//   command paths   position: 30 Hz pulse-train updates, 3000 pulses/rev, ≤ 500 kHz;
//                   speed: 12-bit D/A, ±10 V, 1 V per command unit (drive input in V)
//   solver          CVODE BDF, rtol 1e-8, atol 1e-11 rad and 1e-9 rad/s (see truth.cpp)
//   initial play    SimRig draws φ(0) uniformly in [−β, β] at each activation (seeded): the
//                   link rests anywhere in the play
//   variation       none (every RunVariation σ zero)
#include <cstdint>

#include "clearshape/plant/drive.hpp"
#include "clearshape/plant/encoder.hpp"
#include "clearshape/plant/friction.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/plant/joint.hpp"
#include "clearshape/plant/simulation.hpp"
#include "clearshape/rig/contact.hpp"
#include "clearshape/rig/types.hpp"
#include "clearshape/rig/variation.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/signal/speed_path.hpp"

namespace clearshape::rig {

struct RigTruth {
  plant::DriveModel position_drive = plant::DriveModel::thesis_position_mode();
  plant::DriveModel speed_drive = plant::DriveModel::thesis_speed_mode();
  plant::Link link{};
  /// Total angular play 2β in rad; 0 = the link is rigidly fixed to the shaft.
  double clearance_rad = 0.0;
  ContactSpec position_contact{};
  ContactSpec speed_contact{};
  plant::Friction joint_friction{};
  plant::EncoderConfig encoder{};
  plant::GyroscopeConfig gyro{};  ///< sample_rate_hz and seed are set by the rig
  signal::PulseTrainConfig pulse_train{};
  signal::AnalogOutputConfig analog_output{};
  plant::SolverOptions solver{};
  /// SimRig: draw φ(0)/β uniformly in [−1, 1] at each activation (else initial_play_fraction).
  bool random_initial_play = true;
  double initial_play_fraction = 0.0;  ///< φ(0)/β in [−1, 1]
  /// Run-to-run variation SimRig draws at each activation (variation.hpp); simulate_run
  /// (offline.hpp) runs the nominal rig and ignores it.
  RunVariation variation{};

  double half_play_rad() const noexcept { return 0.5 * clearance_rad; }
  const plant::DriveModel& drive(CommandMode mode) const noexcept {
    return mode == CommandMode::position ? position_drive : speed_drive;
  }
  const ContactSpec& contact(CommandMode mode) const noexcept {
    return mode == CommandMode::position ? position_contact : speed_contact;
  }
  /// Throws InvalidArgument naming the field.
  void validate() const;
};

/// The built-in truth: the calibrated thesis rig (values in the header comment). SimRig(options)
/// is built with it.
RigTruth thesis_rig_truth();

/// The uncalibrated physical prior (header comment): calibrate-rig's starting point.
RigTruth uncalibrated_thesis_rig_prior();

/// The plant for a mode. A zero clearance gives a free link that never touches (the rig then
/// copies the motor motion to the link: rigid attachment).
plant::PlantModel plant_model(const RigTruth& truth, CommandMode mode);

/// Converts a command in rig units (rad or V, see Command) to the drive model's command units
/// (position: degrees, the Eq. 4.2 model maps deg → deg; speed: V → deg/s).
double drive_units(CommandMode mode, double value) noexcept;

}  // namespace clearshape::rig
