#pragma once
// Calibration of the simulated rig's truth to the thesis's measurements (DESIGN.md §2) — the
// procedure behind `clearshape calibrate-rig`. It is the one place in the study module that sets
// a truth (rig/truth.hpp); the study runner never reads one.
//
// What is calibrated, and against what (never against shaped results, which stay predictions):
//   1. speed-mode drive      The thesis identified its speed model through the 4th-order 30 rad/s
//                            Butterworth (§3.3), so Eq. 4.2 (speed) describes drive × filter. The
//                            truth's drive is the P3UZ whose step response, filtered by that chain,
//                            best matches the step response of Eq. 4.2 (least squares, NLopt).
//                            Kp is the thesis's (the filter has unit DC gain).
//   2. position mode         play 2β, the flank's stiffness K and damping D (thesis law, exponent
//                            fixed), the gyro's noise density — fitted (NLopt BOBYQA on logs) so
//                            that the rig's unshaped trials reproduce the "without is" means of
//                            Tables B.1–B.5 (log errors); their spread can be weighted in too,
//                            but by default is only reported (the thesis's trial-to-trial spread
//                            comes from the real rig's variation, which the truth does not model).
//   3. speed mode            reported with the same joint (the unshaped mean of Table 5.1 depends
//                            on the step amplitude, a protocol choice).
// Each evaluation runs the real study measurement on a SimRig built with the candidate truth
// (make_sim_rig_with_truth), with fixed seeds: the calibration is deterministic.
#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/lti/process_model.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/study/protocol.hpp"

namespace clearshape::study {

struct DriveChainFit {
  lti::ProcessModel drive{"P1", lti::ProcessParameters{}};  ///< the truth's speed drive
  double rms_error_deg_s = 0.0;  ///< RMS(chain(drive step) − Eq. 4.2 step), unit step
  double relative_error = 0.0;   ///< rms / Kp
  int evaluations = 0;
};

/// Step 1: the speed drive whose filtered unit-step response matches `identified` (the thesis's
/// Eq. 4.2 speed model) over `duration_s` at `sample_time_s`.
DriveChainFit fit_drive_under_chain(const lti::ProcessModel& identified, double duration_s = 2.0,
                                    double sample_time_s = 1e-3, int max_evaluations = 600);

struct RigCalibrationOptions {
  int trials = 4;              ///< unshaped trials per table and evaluation
  int max_evaluations = 80;    ///< NLopt evaluations (position step)
  std::uint64_t seed = 7;      ///< trial seeds
  double spread_weight = 0.0;  ///< weight of the log error of the trials' standard deviation
  int threads = 2;
  std::ostream* progress = nullptr;
};

struct TargetResidual {
  std::string table;  ///< "B.1", …, "5.1"
  std::string input;
  double target_mean = 0.0, target_std = 0.0;
  double ours_mean = 0.0, ours_std = 0.0;
  double relative_error() const { return (ours_mean - target_mean) / target_mean; }
};

struct RigCalibrationResult {
  rig::RigTruth truth;
  DriveChainFit speed_drive;
  std::vector<TargetResidual> residuals;
  int evaluations = 0;
  double objective = 0.0;
  nlohmann::ordered_json to_json() const;
};

/// Unshaped trials of every "none" column of `protocol`'s rig tables on a SimRig with `truth`:
/// mean and standard deviation of Eq. 5.1, next to the thesis's.
std::vector<TargetResidual> unshaped_residuals(const rig::RigTruth& truth, const Protocol& protocol,
                                               int trials, std::uint64_t seed, int threads = 1);

/// Steps 1–3. `start` gives everything not calibrated (encoder, gyro DLPF, paths, …).
RigCalibrationResult calibrate_rig(const Protocol& position, const Protocol& speed,
                                   const rig::RigTruth& start, const RigCalibrationOptions& options);

/// The calibrated parts of a truth as a `clearshape simulate --config` / `clearshape study
/// --rig-config` TOML file (joint, contact, link, gyroscope, and the speed drive when given).
std::string truth_to_toml(const rig::RigTruth& truth, const std::string& header_comment,
                          const lti::ProcessModel* speed_drive = nullptr);

}  // namespace clearshape::study
