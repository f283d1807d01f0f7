#include "clearshape/rig/truth.hpp"

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/lti/process_model.hpp"

namespace clearshape::rig {

void RigTruth::validate() const {
  link.validate();
  require_non_negative("truth.clearance_rad", clearance_rad);
  position_contact.validate();
  speed_contact.validate();
  joint_friction.validate("truth.joint_friction");
  gyro.validate();
  pulse_train.validate();
  analog_output.validate();
  solver.validate();
  require_in_closed("truth.initial_play_fraction", initial_play_fraction, -1.0, 1.0);
  variation.validate();
  if (position_drive.mode() != plant::DriveMode::position) {
    throw InvalidArgument("truth.position_drive is a speed-mode drive; allowed: a position-mode drive");
  }
  if (speed_drive.mode() != plant::DriveMode::speed) {
    throw InvalidArgument("truth.speed_drive is a position-mode drive; allowed: a speed-mode drive");
  }
}

RigTruth uncalibrated_thesis_rig_prior() {
  RigTruth t;
  t.clearance_rad = deg_to_rad(1.0);             // total backlash 1° (a physical guess)
  t.link.inertia_kg_m2 = 5.0e-3;                 // bar + gyroscope + added tip mass
  t.link.mass_kg = 0.0;                          // vertical axis: no gravity torque
  t.link.ground_viscous_n_m_s_per_rad = 1e-4;    // air and the gyroscope cable
  t.position_contact = ContactSpec::thesis_for(CommandMode::position);
  t.speed_contact = ContactSpec::thesis_for(CommandMode::speed);
  t.joint_friction.viscous = 1e-3;               // lubricated play, N·m·s/rad
  t.encoder = plant::EncoderConfig{};            // 3000 lines ×4
  t.gyro = plant::GyroscopeConfig{};             // ITG-3205 datasheet values
  t.gyro.low_pass = plant::GyroLowPass::hz42;
  t.pulse_train = signal::PulseTrainConfig{};    // 30 Hz, 3000 pulses/rev, 500 kHz
  t.analog_output = signal::AnalogOutputConfig{};  // 12 bit, ±10 V, 1 V per unit
  // rtol 1e-8: with the contact law's kinks located (tests/plant/test_kinks.cpp) the calibrated
  // rig's 10 s steps agree with rtol 1e-11 to 4e-7 (position) and 3e-6 (speed) of the link
  // rate's peak, and with SciPy's solve_ivp (bench/simulate_peer.py) to ~5e-7.
  t.solver.relative_tolerance = 1e-8;
  t.solver.angle_tolerance_rad = 1e-11;
  t.solver.rate_tolerance_rad_s = 1e-9;
  t.random_initial_play = true;
  return t;
}

RigTruth thesis_rig_truth() {
  // Output of `clearshape calibrate-rig` (defaults), recorded with its residuals in
  // studies/sim-rig-truth.toml (summary in truth.hpp).
  RigTruth t = uncalibrated_thesis_rig_prior();
  lti::ProcessParameters speed;  // the speed drive under the 30 rad/s chain (thesis §3.3)
  speed.kp = 25.47;
  speed.tz = 0.13063670461642587;
  speed.zeta = 0.46822267754433256;
  speed.tw = 0.04163926480328696;
  speed.tp3 = 0.1540438071706051;
  t.speed_drive = plant::DriveModel::from_process_model(plant::DriveMode::speed, lti::ProcessModel("P3UZ", speed));
  t.clearance_rad = deg_to_rad(0.03200701024612477);
  t.position_contact.model = ContactModel::thesis;  // Eq. 4.3 with a linear flank (n = 1)
  t.position_contact.stiffness = 45.158834415041305;
  t.position_contact.exponent = 1.0;
  t.position_contact.damping = 0.12355192243621643;
  t.speed_contact = t.position_contact;  // one joint
  t.gyro.noise_density_dps_per_rthz = 0.013974292038526556;
  // Run-to-run variation (variation.hpp), fitted to Tables 4.1–4.2 and the trials' spread.
  t.variation.position_gain_rel_sigma = 8.037489095040713e-05;
  t.variation.speed_gain_rel_sigma = 0.002864760507229867;
  t.variation.start_latency_max_s = 0.0005123437272557567;
  t.variation.analog_noise_v = 0.004149698164202801;
  t.variation.analog_offset_sigma_v = 0.0010967269177501143;
  t.variation.flank_damping_rel_sigma = 0.1775986653339299;
  return t;
}

plant::PlantModel plant_model(const RigTruth& truth, CommandMode mode) {
  plant::PlantModel model;
  model.drive = truth.drive(mode);
  model.link = truth.link;
  plant::TorsionalClearance joint;
  const ContactSpec& contact = truth.contact(mode);
  joint.law = make_contact_law(contact, truth.link.inertia_kg_m2);
  joint.impact = make_impact_law(contact);
  joint.joint_friction = truth.joint_friction;
  // Zero clearance: the link is rigid on the shaft; the plant then carries a free link that
  // never reaches a stop (a play of ±1000 rad) and the rig copies the motor motion to it.
  joint.half_play_rad = truth.clearance_rad > 0.0 ? truth.half_play_rad() : 1e3;
  if (truth.clearance_rad == 0.0) joint.impact.reset();
  model.joint = joint;
  model.validate();
  return model;
}

double drive_units(CommandMode mode, double value) noexcept {
  return mode == CommandMode::position ? rad_to_deg(value) : value;
}

}  // namespace clearshape::rig
