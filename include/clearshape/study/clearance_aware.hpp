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
// (metrics/mean_deviation.hpp, searched from the move's start) over every move m and every
// uncertainty point u (play × f_p, stiffness × f_K, the link's initial place in the play),
// J(a) = max_{m,u} MD(m, u; a) + 0.1 · mean_{m,u} MD(m, u; a)
// (the mean term breaks ties between designs with the same worst case). Each case is one
// simulation of the model through the mode's command path (study::simulate_command).
//
// Search: NLopt LN_SBPLX (Rowan's subplex, derivative-free: MD is not smooth in a) from two
// starts — the unshaped step and the uniform staircase (a constant-velocity move over the
// bound) — the evaluation budget split between them. Cases run in parallel (std::thread, a
// fixed assignment of cases to threads, results reduced in case order): the result does not
// depend on the thread count or on timing. No randomness.
#include <string>
#include <vector>

#include "clearshape/shaping/shaper.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::study {

/// One point of the model's uncertainty set.
struct UncertaintyPoint {
  double play_factor = 1.0;            ///< × the model's play, (0, 10]
  double stiffness_factor = 1.0;       ///< × the model's K, (0, 100]
  double initial_play_fraction = 0.0;  ///< φ(0)/β: where the link rests at the start, [−1, 1]
};

/// Nominal at the centre of the play; play −20 % with half the stiffness resting on the rear
/// flank; play +20 % with twice the stiffness on the front flank.
std::vector<UncertaintyPoint> default_uncertainty();

struct ClearanceAwareRequest {
  ClearanceModel model;
  std::vector<double> moves;           ///< step amplitudes, command units (deg), each != 0
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
  double move = 0.0;
  UncertaintyPoint point;
  double md_unshaped_deg = 0.0;
  double md_shaped_deg = 0.0;
};

struct ClearanceAwareResult {
  shaping::Shaper shaper{"clearance-aware", {{0.0, 1.0}}};
  double objective = 0.0;              ///< J at the result
  double worst_md_deg = 0.0;           ///< max over cases, shaped
  double worst_unshaped_md_deg = 0.0;  ///< max over cases, unshaped
  std::vector<ClearanceAwareCase> cases;  ///< moves × uncertainty, move-major
  int evaluations = 0;
  std::string termination;             ///< NLopt's result of the better start
};

/// The design. Throws InvalidArgument on a bad request, RuntimeError if NLopt fails.
ClearanceAwareResult design_clearance_aware(const ClearanceAwareRequest& request);

/// Eq. 5.1 of the link angle of `model` under `move` shaped by `shaper` (start at
/// request.move_start_s, through the command path) — one case of the objective.
double clearance_aware_case_md(const ClearanceAwareRequest& request, const ClearanceModel& model,
                               double move, double initial_play_fraction, const shaping::Shaper& shaper);

}  // namespace clearshape::study
