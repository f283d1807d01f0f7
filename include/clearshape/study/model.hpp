#pragma once
// The study's model of the rig, built only from what the study measured (thesis §4.2,
// Fig. 4.18): the identified drive (Eq. 4.2 process model) and a link on a torsional play with
// the thesis contact law F = K δⁿ + D δ̇ (Eq. 4.3, clamped at F ≥ 0). It is simulated with the
// plant module (CVODE) and the drive command paths of the signal module with their published
// settings (§3.2: 30 Hz pulse updates, 3000 pulses/rev, 500 kHz; 12-bit ±10 V D/A).
//
// The joint's friction (thesis Eq. 2.9, F_T = −μ F_N v_T/|v_T|, here as a bearing torque on the
// link–motor relative rate φ̇ with its sign regularized as the plant does, plant/friction.hpp):
// τ_f = −c·tanh(φ̇/v_t) − b·φ̇. It decides where a link that leaves its flank stops in the play.
//
// Position mode: the pulse generator programs a target at its next 30 Hz update, one update
// period after it was written (the rig reports the commanded position it actually applied, and
// the clearance fit uses that record directly).
#include <exception>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/plant/joint.hpp"
#include "clearshape/rig/types.hpp"

namespace clearshape::study {

/// The flank's contact law: the thesis's Eq. 4.3 (K δⁿ + D δ̇, clamped at F ≥ 0) or the Flores
/// et al. (2011) restitution law F = K δⁿ (1 + 8(1−e)/(5e)·δ̇/δ̇⁻) (plant::Hysteresis::flores,
/// the large-play truth's law; D unused).
enum class ContactLawChoice { dashpot, flores };

/// "dashpot", "flores"; and back (InvalidArgument naming the allowed names).
std::string to_string(ContactLawChoice law);
ContactLawChoice contact_law_from_string(const std::string& name);

struct ClearanceModel {
  rig::CommandMode mode = rig::CommandMode::position;
  lti::ProcessModel drive{"P1", lti::ProcessParameters{}};  ///< command units → deg or deg/s
  double link_inertia_kg_m2 = 5e-3;
  double play_rad = 0.0;        ///< total play 2β (0: rigid)
  double stiffness = 1e4;       ///< K, N·m/rad^n
  double exponent = 1.5;        ///< n
  double damping = 300.0;       ///< D, N·m·s/rad (dashpot law)
  ContactLawChoice contact_law = ContactLawChoice::dashpot;
  double restitution = 0.6;     ///< e ∈ (0, 1] (flores law)
  double coulomb_n_m = 0.0;     ///< c: the joint's Coulomb torque (Eq. 2.9, regularized), 0: none
  double viscous_n_m_s_per_rad = 0.0;          ///< b: viscous on the relative rate, 0: none
  double friction_regularization_rad_s = 1e-3;  ///< v_t of tanh(φ̇/v_t) (the large-play truth's)
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

/// The plant (plant/joint.hpp) the model describes: its drive, link, play, law and friction.
plant::PlantModel plant_of(const ClearanceModel& model);

/// Simulates the model under the command the drive received (sampled at sample_time_s, held
/// between samples: e.g. a record's command_applied). The link starts at rest at
/// `initial_play_fraction` × β in the play (0: the centre). `design_accuracy`: a design loop's
/// accuracy — the fixed-step path (plant/fixed_step.hpp) for a linear dashpot flank, else CVODE
/// at rtol 1e-6 without energy integrals — instead of the fit's CVODE at rtol 1e-7. Throws
/// RuntimeError on integration failure.
ModelResponse simulate_drive_command(const ClearanceModel& model, const UniformSeries& drive_command,
                                     double duration_s, double initial_play_fraction = 0.0,
                                     bool design_accuracy = false);

/// One simulation of a design loop's batch: simulate_drive_command's arguments with
/// design_accuracy (pointers not owned; they must outlive the call).
struct DriveCommandJob {
  const ClearanceModel* model = nullptr;
  const UniformSeries* drive_command = nullptr;
  double duration_s = 0.0;
  double initial_play_fraction = 0.0;
};

/// Each job's response, or the error simulate_drive_command would have thrown for it.
struct DriveCommandOutcome {
  ModelResponse response;
  std::exception_ptr error;  ///< null on success
};

/// simulate_drive_command(…, design_accuracy = true) for every job, in order, with the same
/// responses to the bit and the same errors. Neighbouring jobs on the fixed-step path with the
/// same length and step are simulated two at a time (plant::simulate_fixed_steps: about 1.5 times
/// the throughput); a pair that fails is simulated again one job at a time, so an error stays
/// with its job.
std::vector<DriveCommandOutcome> simulate_drive_commands(std::span<const DriveCommandJob> jobs);

/// The drive command a requested command (command units) becomes through the mode's command path
/// (as simulate_command applies it), on the grid of `duration_s`.
UniformSeries drive_command_of(const ClearanceModel& model, const UniformSeries& command, double duration_s);

/// Simulates the model under a requested command (command units), through the mode's command
/// path (position: the rig's real-time 30 Hz pulse path — at the first sample tick at or after
/// each update instant the command written then becomes the target, reached by the next instant;
/// speed: 12-bit D/A).
ModelResponse simulate_command(const ClearanceModel& model, const UniformSeries& command,
                               double duration_s, double initial_play_fraction = 0.0,
                               bool design_accuracy = false);

/// The clearance fit (thesis §4.2, Fig. 4.19–4.20): the Eq. 4.3 parameters for which the model's
/// link rate under `drive_command` matches a measured link rate in the least-squares sense.
/// The link inertia stays fixed: the gyro record determines only K/J and D/J.
struct ClearanceFitProblem {
  ClearanceModel start;  ///< drive, link inertia (fixed) and the values of fixed parameters
  UniformSeries drive_command;                    ///< what the drive received (command_applied)
  std::vector<double> measured_link_rate_deg_s;  ///< on the command's grid, from t = 0
  /// Robust to the run-to-run variation (optional, empty: unused): the mean over the runs of each
  /// run's link-rate envelope (mean_rate_envelope_deg_s), on the command's grid. Runs whose
  /// impacts fall at different times average to a smeared record, which least squares explains
  /// best with a link that stops at once (too much friction); their envelopes do not cancel.
  /// When given, the objective's mean square adds envelope_weight × the envelope's.
  std::vector<double> measured_link_rate_envelope_deg_s;
  double envelope_window_s = 0.05;  ///< the envelope's moving-RMS window
  double envelope_weight = 1.0;
  double duration_s = 2.0;
  /// Of stiffness, damping, play, exponent, coulomb, viscous (the joint's friction, Eq. 2.9).
  /// With start.contact_law flores the dissipation parameter is the restitution e ("restitution",
  /// or "damping" read as it), fitted in [0.05, 1] from e = exp(−πζ/√(1−ζ²)) of the link mode.
  std::vector<std::string> free{"stiffness", "damping"};
  /// The link's identified residual mode (0: unknown): start K/J = ω² and D/J = 2ζω (linear
  /// flank, then mapped to each exponent at the reference deflection); otherwise `start`'s K, D.
  double link_natural_frequency_rad_s = 0.0;
  double link_damping_ratio = 0.0;
  std::vector<double> exponent_grid{1.0, 1.5, 2.0};  ///< multi-start values of n (exponent free)
  double exponent_min = 1.0;  ///< n bounds: linear flank .. beyond Hertz
  double exponent_max = 2.5;
  /// The link sensor's first-order low-pass (y += a(x − y), a = 1 − exp(−2π f_c T_s), as the
  /// gyroscope model) applied to the model's link rate before the comparison: the bandwidths to
  /// choose from, 0 = none (e.g. the ITG-3205 DLPF settings). The one that explains the record
  /// best at the start, re-checked at the optimum, is used.
  std::vector<double> sensor_low_pass_grid_hz{0.0};
  int max_evaluations = 150;   ///< per local search (BOBYQA)
  /// Convergence: final trust radius in the fit variables (log K_ref, log D, log play: relative;
  /// n: absolute), i.e. parameters to ≈ 0.1 %.
  double step_tolerance = 1e-3;
};

/// One fitted parameter, with its local (Gauss–Newton) uncertainty.
struct ClearanceParameter {
  std::string name;        ///< stiffness, damping (restitution: flores law), play, exponent, coulomb, viscous
  double value = 0.0;      ///< SI (K N·m/rad^n, D N·m·s/rad, play rad, n)
  double start = 0.0;
  bool free = false;
  bool at_bound = false;   ///< ended on a bound of the search (n = 1, the linear law, is the
                           ///< law's own limit, not a search bound: a fit there is a finding)
  /// 1σ of log(value) (i.e. relative) for K, D, play; of n itself for the exponent; NaN if fixed
  /// or singular. From σ²(JᵀJ)⁻¹ with σ² over the residual's effective sample count.
  double std_error = 0.0;
  bool identifiable = false;  ///< free, finite 1σ below 10 % (n: below 0.1)
};

/// One local search of the multi-start (n held at `exponent`, or free for the final refinement).
struct ClearanceFitStart {
  double exponent = 0.0;
  bool exponent_free = false;
  double rms_error_deg_s = 0.0;  ///< the search objective's RMS (record and envelope, if any)
  int evaluations = 0;
  std::string termination;  ///< NLopt result name
};

struct ClearanceFitResult {
  ClearanceModel model;
  ClearanceModel start_model;        ///< the data-derived start (first grid exponent)
  double rms_error_deg_s = 0.0;      ///< of the link rate (with an envelope: that part alone)
  double envelope_rms_error_deg_s = 0.0;  ///< of the envelope (0: no envelope record)
  double start_rms_error_deg_s = 0.0;  ///< the search objective's at the start
  double agreement = 0.0;            ///< Eq. 4.1: RMS(model − measured) / range(measured)
  double reference_deflection_rad = 0.0;  ///< K_ref = K·δ_ref^(n−1) is the fitted stiffness variable
  double sensor_low_pass_hz = 0.0;   ///< the chosen sensor bandwidth (0: none)
  std::vector<std::pair<double, double>> sensor_low_pass_scan;  ///< (f_c Hz, RMS deg/s) at the optimum
  int evaluations = 0;               ///< model simulations over all searches (not the 1σ ones)
  std::string termination;           ///< NLopt result of the search that produced `model`
  bool converged = false;            ///< that search met its xtol/ftol criterion
  std::vector<ClearanceFitStart> starts;
  std::vector<ClearanceParameter> parameters;  ///< stiffness, damping, play, exponent
};

/// Fits the problem: start from the link mode, coarse scans of K_ref and the play, a loose K–D
/// search, variables scaled by their sensitivity, NLopt BOBYQA on the mean square from every
/// exponent of `exponent_grid` (n held), then one search with n free from the best (the sensor
/// bandwidth profiled over its grid until then, fixed for it), basin hops in the play. Throws InvalidArgument on an ill-posed problem (a free parameter that is
/// unknown, non-finite or non-positive at the start, mismatched lengths) and RuntimeError when
/// NLopt fails (invalid arguments, out of memory); a search that ends at `max_evaluations` or on
/// round-off is reported with `converged == false`, never silently.
ClearanceFitResult fit_clearance(const ClearanceFitProblem& problem);

/// The unit of a fitted parameter's value as the outputs write it (the play in deg): "N·m/rad^n",
/// "N·m·s/rad", "deg", "1" (exponent, restitution), "N·m" (coulomb), "N·m·s/rad" (viscous); ""
/// for an unknown name.
std::string clearance_parameter_unit(const std::string& name);

/// A link rate's envelope: the centred moving RMS over window_s (the window cut at the record's
/// ends), with `noise_variance` ((deg/s)²) removed and floored at 0.
std::vector<double> rate_envelope_deg_s(const std::vector<double>& rate, double window_s, double sample_time_s,
                                        double noise_variance = 0.0);

/// The mean envelope of several records over their first `samples` samples, each with its own
/// rest noise removed: the variance of its first `rest_samples` samples (0: none).
std::vector<double> mean_rate_envelope_deg_s(const std::vector<std::vector<double>>& records, std::size_t samples,
                                             double window_s, double sample_time_s, std::size_t rest_samples);

/// The sensor's first-order low-pass of `clearance_fit`, in place (0: no filtering).
void apply_sensor_low_pass(std::vector<double>& rate, double bandwidth_hz, double sample_time_s);

/// What the gyro reports for a model response: its link rate (deg/s) through the sensor
/// low-pass at `low_pass_hz` (0: none), sampled like the problem's drive command.
std::vector<double> sensed_link_rate_deg_s(const ClearanceFitProblem& problem,
                                           const ModelResponse& response, double low_pass_hz);

/// Eq. 4.1 with the measurement as the mean signal: RMS(model − measured) / range(measured).
double clearance_agreement(const std::vector<double>& measured, const std::vector<double>& model);

// --- The per-run joint fit (issue 19): runs that started at different places in the play are
// never averaged; each keeps its own start place as a nuisance parameter.

/// One record of a per-run fit: what the drive received and what the gyro measured.
struct ClearanceRunRecord {
  std::string id;                       ///< for the outputs (the run id)
  UniformSeries drive_command;          ///< command_applied, from t = 0
  std::vector<double> link_rate_deg_s;  ///< the gyro's link rate on the command's grid
};

/// The per-run fit: the joint's play, flank (K, D; n held) and friction (Coulomb c, viscous b)
/// shared by every run, and each run's start place φ(0)/β ∈ [−1, 1] its own, fitted by
/// Levenberg–Marquardt on the gyro records (each with its resting bias removed).
struct ClearanceRunsFitProblem {
  ClearanceModel start;  ///< drive, link inertia, contact law; start K, D, play, c, b, n
  std::vector<ClearanceRunRecord> runs;
  double duration_s = 2.0;   ///< record length compared, from t = 0
  double rest_s = 0.4;       ///< the gyro bias window before the move: its mean is removed per run
  /// Shared parameters fitted: of stiffness, damping, play, coulomb, viscous (n held at
  /// start.exponent; its freedom is checked afterwards).
  std::vector<std::string> free{"stiffness", "damping", "play", "coulomb", "viscous"};
  double link_natural_frequency_rad_s = 0.0;  ///< the link mode (0: unknown): K/J = ω², D/J = 2ζω
  double link_damping_ratio = 0.0;
  std::vector<double> sensor_low_pass_grid_hz{0.0};  ///< as ClearanceFitProblem
  /// The flank damping varies from run to run (lubrication, temperature; rig/variation.hpp):
  /// each run its own D as a nuisance, the reported D their geometric mean. Off: D shared.
  bool per_run_damping = true;
  int max_iterations = 40;   ///< Levenberg–Marquardt iterations
  int threads = 2;           ///< simulations in parallel (results do not depend on it)
  bool check_exponent = true;  ///< the n-free alternative (score test at n = 1)
};

/// The relative 1σ of the parameters a command design needs (design stage's uncertainty set).
struct ClearanceModelSigma {
  double play_rel_sigma = 0.0;
  double stiffness_rel_sigma = 0.0;
  double coulomb_rel_sigma = 0.0;
  /// The flank damping's run-to-run spread (1σ of ln D over the runs, at its one-sided 90 %
  /// upper confidence bound): a variation the rig has, not an estimate's error. 0: not known.
  double damping_spread = 0.0;
};

/// The one-sided upper confidence bound on the standard deviation of `log_values` (χ² with
/// n − 1 degrees of freedom: Montgomery, Applied Statistics, §7.4): the spread the runs cannot
/// exclude. 0 for fewer than 3 values. `confidence` in (0, 1).
double spread_upper_bound(const std::vector<double>& log_values, double confidence = 0.9);

struct ClearanceRunsFitResult {
  ClearanceModel model;
  /// stiffness, damping, play, exponent, coulomb, viscous; std_error relative (1σ / value) for
  /// all but the exponent (absolute): the larger of the noise-based σ²(JᵀJ)⁻¹ (AR(1)-inflated)
  /// and the run-clustered sandwich (run-to-run scatter the model does not carry). With
  /// per-run damping, D is the runs' geometric mean and its 1σ their scatter's standard error.
  std::vector<ClearanceParameter> parameters;
  std::vector<std::string> run_ids;
  std::vector<double> start_fraction;      ///< per run: φ(0)/β
  std::vector<double> start_fraction_std;  ///< its 1σ (absolute)
  std::vector<double> run_damping;         ///< per run: D (N·m·s/rad; all equal when shared)
  std::vector<double> run_rms_error_deg_s; ///< per run
  double rms_error_deg_s = 0.0;            ///< over all runs (fixed-step model)
  double check_rms_error_deg_s = 0.0;      ///< the optimum re-simulated with CVODE (rtol 1e-7)
  double sensor_low_pass_hz = 0.0;
  int iterations = 0;
  int simulations = 0;
  bool converged = false;
  std::string termination;
  /// The n-free alternative: the Gauss–Newton step in n from n = 1 with the others re-fitted,
  /// its 1σ and the χ²₁ statistic of the residual it removes (significant above 3.84, 5 %).
  double exponent_free_value = 1.0;
  double exponent_free_std = 0.0;
  double exponent_chi2 = 0.0;
  bool exponent_free_better = false;
  ClearanceModelSigma sigma() const;
};

/// Fits the problem (coarse scans of the play and the Coulomb torque with each run's start place
/// profiled, then Levenberg–Marquardt on everything). Throws InvalidArgument naming the field on
/// an ill-posed problem (no runs, records shorter than duration_s, an unknown free parameter).
ClearanceRunsFitResult fit_clearance_runs(const ClearanceRunsFitProblem& problem);

}  // namespace clearshape::study
