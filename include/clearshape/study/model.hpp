#pragma once
// The study's model of the rig, built only from what the study measured (thesis §4.2,
// Fig. 4.18): the identified drive (Eq. 4.2 process model) and a link on a torsional play with
// the thesis contact law F = K δⁿ + D δ̇ (Eq. 4.3, clamped at F ≥ 0). It is simulated with the
// plant module (CVODE) and the drive command paths of the signal module with their published
// settings (§3.2: 30 Hz pulse updates, 3000 pulses/rev, 500 kHz; 12-bit ±10 V D/A).
//
// Position mode: the pulse generator programs a target at its next 30 Hz update, one update
// period after it was written (the rig reports the commanded position it actually applied, and
// the clearance fit uses that record directly).
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/rig/types.hpp"

namespace clearshape::study {

struct ClearanceModel {
  rig::CommandMode mode = rig::CommandMode::position;
  lti::ProcessModel drive{"P1", lti::ProcessParameters{}};  ///< command units → deg or deg/s
  double link_inertia_kg_m2 = 5e-3;
  double play_rad = 0.0;        ///< total play 2β (0: rigid)
  double stiffness = 1e4;       ///< K, N·m/rad^n
  double exponent = 1.5;        ///< n
  double damping = 300.0;       ///< D, N·m·s/rad
};

/// The model's response, sampled like a record (no sensor noise or quantization).
struct ModelResponse {
  double sample_time_s = 1e-3;
  std::vector<double> time_s;
  std::vector<double> drive_command;    ///< what reached the drive (command units)
  std::vector<double> motor_angle_deg;
  std::vector<double> motor_rate_deg_s;
  std::vector<double> link_angle_deg;   ///< relative to its value at t = 0
  std::vector<double> link_rate_deg_s;
};

/// Simulates the model under the command the drive received (sampled at sample_time_s, held
/// between samples: e.g. a record's command_applied). Throws RuntimeError on integration failure.
ModelResponse simulate_drive_command(const ClearanceModel& model, const UniformSeries& drive_command,
                                     double duration_s);

/// Simulates the model under a requested command (command units), through the mode's command
/// path (position: 30 Hz pulse train with one update of latency; speed: 12-bit D/A).
ModelResponse simulate_command(const ClearanceModel& model, const UniformSeries& command,
                               double duration_s);

}  // namespace clearshape::study
