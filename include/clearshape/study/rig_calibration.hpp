#pragma once
// Calibration of the simulated rig's truth to the thesis's measurements (docs/design.md §2) — the
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
//   4. run-to-run variation  the RunVariation σ's (rig/variation.hpp: drive gain scatter per mode,
//                            start latency, D/A noise and offset, flank damping scatter) — fitted
//                            (NLopt BOBYQA on logs, joint fixed) so that repeated runs reproduce
//                            the mean Eq. 4.1 errors of Tables 4.1–4.2 and the trials' spread of
//                            the unshaped Eq. 5.1 (Tables 5.1, B.1–B.5), with the unshaped means
//                            kept in the objective (log errors throughout).
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

/// One target of step 4: a thesis number and ours.
struct VariationResidual {
  std::string table;     ///< "4.1", "4.2", "5.1", "B.1", …
  std::string input;
  std::string quantity;  ///< "eq41_mean" (mean Eq. 4.1 error), "md_std", "md_mean" (Eq. 5.1, deg or deg/s)
  double target = 0.0, ours = 0.0;
  double log_error() const;  ///< ln(ours / target)
};

struct VariationCalibrationOptions {
  int repetitions = 6;         ///< search: runs per consistency input and trials per table
  int final_repetitions = 10;  ///< the reported residuals (the thesis's 10 runs)
  int max_evaluations = 24;    ///< NLopt evaluations
  std::uint64_t seed = 7;      ///< run seeds (common random numbers across evaluations)
  double mean_weight = 1.0;    ///< weight of the unshaped means' log errors (keeps step 2's fit)
  int threads = 2;
  std::ostream* progress = nullptr;
};

struct VariationCalibrationResult {
  rig::RunVariation variation;
  std::vector<VariationResidual> residuals;  ///< with the fitted variation
  int evaluations = 0;
  double objective = 0.0;
  nlohmann::ordered_json to_json() const;
};

/// Repeated runs on a SimRig with `truth`: the mean Eq. 4.1 error of every consistency input
/// (encoder; speed mode through the §3.3 chain) and the mean and spread of the unshaped Eq. 5.1
/// of every rig table, for both protocols, next to the thesis's.
std::vector<VariationResidual> variation_residuals(const rig::RigTruth& truth, const Protocol& position,
                                                   const Protocol& speed, int repetitions,
                                                   std::uint64_t seed, int threads = 1);

/// Step 4 alone: fits truth.variation (the rest of `truth` fixed).
VariationCalibrationResult calibrate_variation(const Protocol& position, const Protocol& speed,
                                               const rig::RigTruth& truth,
                                               const VariationCalibrationOptions& options);

struct RigCalibrationOptions {
  int trials = 4;              ///< unshaped trials per table and evaluation
  int max_evaluations = 80;    ///< NLopt evaluations (position step)
  std::uint64_t seed = 7;      ///< trial seeds
  double spread_weight = 0.0;  ///< weight of the log error of the trials' standard deviation
  int variation_evaluations = 24;  ///< step 4's evaluations; 0 keeps start.variation
  bool fit_joint = true;           ///< step 2; false keeps start's play, flank and gyro noise
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
  VariationCalibrationResult variation;  ///< step 4 (evaluations 0 when skipped)
  int evaluations = 0;
  double objective = 0.0;
  nlohmann::ordered_json to_json() const;
};

/// Unshaped trials of every "none" column of `protocol`'s rig tables on a SimRig with `truth`:
/// mean and standard deviation of Eq. 5.1, next to the thesis's.
std::vector<TargetResidual> unshaped_residuals(const rig::RigTruth& truth, const Protocol& protocol,
                                               int trials, std::uint64_t seed, int threads = 1);

/// Steps 1–4. `start` gives everything not calibrated (encoder, gyro DLPF, paths, …) and the
/// variation used in step 2 (and kept when step 4 is skipped).
RigCalibrationResult calibrate_rig(const Protocol& position, const Protocol& speed,
                                   const rig::RigTruth& start, const RigCalibrationOptions& options);

/// The calibrated parts of a truth as a `clearshape simulate --config` / `clearshape study
/// --rig-config` TOML file (joint, contact, link, gyroscope, variation, and the speed drive when
/// given).
std::string truth_to_toml(const rig::RigTruth& truth, const std::string& header_comment,
                          const lti::ProcessModel* speed_drive = nullptr);

}  // namespace clearshape::study
