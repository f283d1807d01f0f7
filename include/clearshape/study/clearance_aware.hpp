#pragma once
// Clearance-aware command design (issue 12; docs/large-play.md): a positive input shaper
// optimized by simulation on the IDENTIFIED NONLINEAR model — drive model + play + contact law,
// study::ClearanceModel as `clearshape fit-clearance` or a study's clearance stage gives it —
// for the moves the user names and an uncertainty set of the model, instead of designed from a
// linear mode.
//
// The shaper: impulses on the command path's own time grid (position mode: the 30 Hz pulse
// updates — the driver cannot resolve a finer time, so a finer impulse time only changes which
// update carries it) from t = 0 up to a duration bound (e.g. the linear ZVDD's, so the design
// never adds more delay than ZVDD). Amplitudes a_k = x_k / Σx, x_k ∈ [0, 1]: positive, ΣA = 1.
//
// The objective, for amplitudes a: the worst Eq. 5.1 mean deviation of the link angle
// (metrics/mean_deviation.hpp, searched from the move's start) RELATIVE TO THE SAME CASE
// UNSHAPED, over every move m and every uncertainty point u (play × f_p, stiffness × f_K,
// Coulomb torque × f_c, the link's initial place in the play: issue 19 asks for ≥ 90 % from every
// start, for every move, so each case is judged by its own improvement),
// r(m, u; a) = MD(m, u; a) / MD(m, u; unshaped),  J(a) = max_{m,u} r + 0.1 · mean_{m,u} r
// (the mean term breaks ties between designs with the same worst case). Each case is one
// simulation of the model through the mode's command path (study::simulate_command; the
// fixed-step path of plant/fixed_step.hpp for a linear flank, CVODE otherwise).
//
// Search: NLopt LN_SBPLX (Rowan's subplex, derivative-free: MD is not smooth in a) on J with the
// max replaced by the power mean (mean r⁸)^(1/8) (smooth where the max has kinks), from three
// starts — the unshaped step, the uniform staircase (a constant-velocity move over the bound)
// and the ZV pair at the flank's linear mode √(K/J) placed on the grid — each for a sixth of the
// evaluation budget; the best continues with the rest. Cases run in parallel (std::thread, a
// fixed assignment of cases to threads, results reduced in case order): the result does not
// depend on the thread count or on timing. No randomness.
#include <optional>
#include <string>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/shaping/shaper.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::study {

/// One point of the model's uncertainty set.
struct UncertaintyPoint {
  double play_factor = 1.0;            ///< × the model's play, (0, 10]
  double stiffness_factor = 1.0;       ///< × the model's K, (0, 100]
  double initial_play_fraction = 0.0;  ///< φ(0)/β: where the link rests at the start, [−1, 1]
  double coulomb_factor = 1.0;         ///< × the model's Coulomb torque, [0, 10]
  double damping_factor = 1.0;         ///< × the model's flank damping D (dashpot law), (0, 10]
};

/// The start places a design must hold from (issue 19): −1, −½, 0, ½, 1 of the half play.
std::vector<double> default_start_fractions();

/// Every start place at each model point: the nominal model, and with σ's given (relative 1σ of
/// the fit, 0: not known) its two corners (play −σ, K −σ, Coulomb +σ) and (play +σ, K +σ,
/// Coulomb −σ) — the directions that move the link's release and arrival earliest and latest.
/// With `damping_spread` (the run-to-run 1σ of ln D the runs show, 0: none) also the nominal
/// joint with D × e^(∓spread): a flank damping the rig really varies by, not an estimate's error.
std::vector<UncertaintyPoint> uncertainty_set(double play_rel_sigma = 0.0, double stiffness_rel_sigma = 0.0,
                                              double coulomb_rel_sigma = 0.0,
                                              const std::vector<double>& start_fractions = default_start_fractions(),
                                              double damping_spread = 0.0);

/// The nominal model from every default start place (uncertainty_set()).
std::vector<UncertaintyPoint> default_uncertainty();

/// The set a design from a fitted model uses (the study's stage and `shape --model`): the fit's
/// ±1σ corners (each σ capped at 50 %, a non-finite one read as 50 %) unless every σ is under 2 %
/// (then they are the nominal joint within the design model's accuracy), and the flank damping's
/// run spread (capped at 1) whenever it is known.
std::vector<UncertaintyPoint> design_uncertainty(const ClearanceModelSigma& sigma);

/// One move of the design: the requested command (command units, from t = 0 on the design's
/// sample grid), where its motion ends, and where its last move starts (Eq. 5.1's steady state
/// is searched from there, as the study does).
struct DesignMove {
  std::string name;
  UniformSeries command;
  double motion_end_s = 0.0;
  double last_move_start_s = 0.0;
};

struct ClearanceAwareRequest {
  ClearanceModel model;
  std::vector<double> moves;           ///< step amplitudes, command units (deg), each != 0
  /// Command profiles (e.g. a study's inputs); when given they replace `moves`, rise_s and
  /// move_start_s. Each is simulated for its own length plus max_duration_s + settle_s.
  std::vector<DesignMove> profiles;
  std::vector<UncertaintyPoint> uncertainty = default_uncertainty();
  double max_duration_s = 0.0;         ///< last impulse at or before this, (0, 5] s
  double grid_s = 1.0 / 30.0;          ///< impulse-time grid (position mode: the pulse update)
  double rise_s = 0.0;                 ///< each move's ramp (0: a step; the pulse path ramps it)
  double move_start_s = 0.2;           ///< rest before the move
  double settle_s = 1.0;               ///< simulated after the last impulse's ramp ends
  double sample_time_s = 1e-3;
  int max_evaluations = 80;            ///< objective evaluations over both starts, >= 10
  int threads = 0;                     ///< parallel simulations; 0: the hardware's threads
  /// Throws InvalidArgument naming the field and its range.
  void validate() const;
};

struct ClearanceAwareCase {
  std::string move_name;               ///< the profile's name, or the step's amplitude
  double move = 0.0;                   ///< the step amplitude (profiles: the command's final value)
  UncertaintyPoint point;
  double md_unshaped_deg = 0.0;
  double md_shaped_deg = 0.0;
};

struct ClearanceAwareResult {
  shaping::Shaper shaper{"clearance-aware", {{0.0, 1.0}}};
  double objective = 0.0;              ///< J at the result
  double worst_md_deg = 0.0;           ///< max over cases, shaped
  double worst_unshaped_md_deg = 0.0;  ///< max over cases, unshaped
  double worst_ratio = 0.0;            ///< max over cases of shaped / unshaped MD
  /// Some case ends worse than unshaped (worst_ratio > 1): never offer the design without saying
  /// so (issue 19 "never worse").
  bool worse_than_unshaped = false;
  std::vector<ClearanceAwareCase> cases;  ///< moves × uncertainty, move-major
  int evaluations = 0;
  std::string termination;             ///< NLopt's result of the better start
};

/// The design. Throws InvalidArgument on a bad request, RuntimeError if NLopt fails.
ClearanceAwareResult design_clearance_aware(const ClearanceAwareRequest& request);

/// A signal as a design move: sampled at `sample_rate_hz` over `record_s`, its rest before the
/// motion cut to about 0.05 s (nothing moves there) and cut after the motion ends; nullopt if it
/// never moves. With `update_period_s` (the drive's update grid, e.g. 1/30 s) only whole runs of
/// update periods are cut, so the grid meets the move where it does in the full record.
std::optional<DesignMove> design_move(const std::string& name, const signal::Signal& signal, double sample_rate_hz,
                                      double record_s, double update_period_s = 0.0);

/// The moves a request designs for: its profiles, or steps of its `moves` amplitudes.
std::vector<DesignMove> design_moves(const ClearanceAwareRequest& request);

/// The model at an uncertainty point (play, K, Coulomb torque and flank damping scaled).
ClearanceModel varied_model(const ClearanceModel& model, const UncertaintyPoint& point);

/// Eq. 5.1 of the link angle of `model` under `move` shaped by `shaper` (through the command
/// path, searched from the end of the move's motion) — one case of the objective.
double clearance_aware_case_md(const ClearanceAwareRequest& request, const ClearanceModel& model,
                               const DesignMove& move, double initial_play_fraction, const shaping::Shaper& shaper);

}  // namespace clearshape::study
