#include "clearshape/study/calibrated_truth.hpp"

#include "clearshape/core/units.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/plant/drive.hpp"

namespace clearshape::study {

rig::RigTruth calibrated_thesis_rig_truth() {
  // Output of `clearshape calibrate-rig` (defaults; see studies/sim-rig-truth.toml for the
  // residuals). Unshaped Eq. 5.1 means, ours vs thesis: B.1 0.3125/0.303, B.2 0.1597/0.141,
  // B.3 0.0829/0.085, B.4 0.2283/0.249, B.5 0.2682/0.277, Table 5.1 0.4454/0.392.
  rig::RigTruth t = rig::thesis_rig_truth();
  lti::ProcessParameters speed;
  speed.kp = 25.47;
  speed.tz = 0.13063670461642587;
  speed.zeta = 0.46822267754433256;
  speed.tw = 0.04163926480328696;
  speed.tp3 = 0.1540438071706051;
  t.speed_drive = plant::DriveModel::from_process_model(plant::DriveMode::speed, lti::ProcessModel("P3UZ", speed));
  t.clearance_rad = deg_to_rad(0.03156594677967514);
  t.position_contact.model = rig::ContactModel::thesis;
  t.position_contact.stiffness = 45.03947330571115;
  t.position_contact.exponent = 1.0;
  t.position_contact.damping = 0.12386269084388334;
  t.speed_contact = t.position_contact;
  t.gyro.noise_density_dps_per_rthz = 0.013803626909717781;
  return t;
}

}  // namespace clearshape::study
