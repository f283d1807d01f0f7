#pragma once
// Take-up command design (issue 12; derivation and numbers in docs/large-play.md): a positive
// shaper on the position command path's 30 Hz grid that makes the link cross the play DURING the
// move, at a time the design chooses, and meet the braking flank with zero relative velocity, so
// that the link rides that flank down to rest instead of crossing the play when the motor stops.
//
// Why a shaper: in position mode the pulse generator holds one velocity per update period T
// (signal/position_path.hpp), so every command there is a staircase of slot velocities v_k, i.e.
// a positive shaper with impulses a_k = v_k·T/θ at t_k = k·T (θ the move).
//
// The profile, slots of T (velocities in the move's direction):
//   lead     v_s   (optional) crosses the play slowly, so the rear flank picks the link up at
//                  ≤ v_s wherever it rests (default v_s = 2β/T: the whole play in one update)
//   carry    v_c   the motor accelerates the link on the rear (driving) flank
//   dip      v_d   the motor slows; the link coasts (its own deceleration is only α_f = T_f/J)
//                  and gains the play 2β on the motor
//   recover  v_r   the motor comes back up to the link's speed just as the gap closes
// then the updates stop and the drive decelerates the link on the front (braking) flank to rest.
// With ω(t) the motor rate (the drive model, Eq. 4.2, under the staircase — exact: the drive's
// motion does not depend on the link in position mode), t₁ its first peak (the link leaves the
// rear flank there), v_l(t) = ω(t₁) − α_f (t − t₁) the coasting link, t₂ the next peak of ω, the
// three unknowns solve
//   T·Σv_k = θ,    ω(t₂) = v_l(t₂),    ∫_{t₁}^{t₂} (v_l − ω) dt = 2β
// (the move, the tangency — zero relative velocity at contact — and the take-up). The start is
// the closed form for a drive that only delays the command (v_c = v_r, (v_c − v_d)·T = 2β):
// v_c = v_r = (θ − v_s T + 2β)/(3T), v_d = v_c − 2β/T; Newton's method with a backtracking line
// search refines it on the drive's response.
//
// Flank keeping, its alternative: the link stays on its driving flank during deceleration only
// while the motor decelerates no faster than α_f = T_f/J (0.4 rad/s² on the large-play rig), so a
// move of θ takes at least 2·√(θ/α_f) — flank_keeping_move_time_s().
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/shaping/shaper.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::study {

/// α_f = c/J (rad/s²): the fastest deceleration the coasting link's own friction gives it, so
/// the fastest the motor may decelerate with the link staying on the driving flank (no load, no
/// gravity: vertical axis). 0 for a frictionless model.
double flank_keeping_deceleration_rad_s2(const ClearanceModel& model) noexcept;

/// The shortest move of `move_rad` with acceleration and deceleration bounded by `a_rad_s2`:
/// 2·√(|θ|/a) (accelerate half way, decelerate the other half). +inf for a <= 0.
double flank_keeping_move_time_s(double move_rad, double a_rad_s2) noexcept;

struct TakeUpRequest {
  ClearanceModel model;               ///< position mode, play > 0
  std::vector<double> moves;          ///< step amplitudes (deg), each |θ| > 0
  double grid_s = 1.0 / 30.0;         ///< the pulse generator's update period, [1e-3, 1] s
  double max_duration_s = 0.1;        ///< last impulse at or before: >= 3T adds the lead slot, >= 2T needed
  double lead_velocity_deg_s = -1.0;  ///< v_s; < 0: 2β/T; 0: no lead slot
  /// Throws InvalidArgument naming the field and its range.
  void validate() const;
};

struct TakeUpMove {
  double move_deg = 0.0;
  shaping::Shaper shaper{"take-up", {{0.0, 1.0}}};
  std::vector<double> slot_velocity_deg_s;  ///< |v_k| per slot (lead, carry, dip, recover)
  double separation_s = 0.0;       ///< t₁ after the first update: the link leaves the rear flank
  double contact_s = 0.0;          ///< t₂: the link meets the braking flank
  double link_rate_deg_s = 0.0;    ///< v_l(t₁)
  double take_up_deg = 0.0;        ///< ∫(v_l − ω) over [t₁, t₂] (= the play)
  double contact_relative_rate_deg_s = 0.0;  ///< v_l(t₂) − ω(t₂) (0 by design)
  /// Largest ω − v_l after t₂ while the link should stay on the braking flank (> 0: the drive
  /// overshoots the link's speed and the link drifts off that flank); and the largest reverse
  /// motor rate after t₂ (> 0: the drive overshoots the target and pulls the flank away).
  double overtake_deg_s = 0.0;
  double reversal_deg_s = 0.0;
  int iterations = 0;
};

struct TakeUpResult {
  std::vector<TakeUpMove> moves;             ///< in request order
  double flank_keeping_deceleration_rad_s2 = 0.0;
  std::vector<double> flank_keeping_move_time_s;  ///< per move: the flank-keeping alternative
};

/// Designs one profile per move. Throws InvalidArgument on a bad request or a move too short
/// for the profile (the dip would need a negative velocity: |θ| below ≈ 4β + v_s·T), with the
/// shortest move the request allows.
TakeUpResult design_take_up(const TakeUpRequest& request);

/// A move's design as the outputs write it (results.json sections.take_up, `shape --json`):
/// move_deg, impulses [{t, a}], slot_velocity_deg_s, separation_s, contact_s, link_rate_deg_s,
/// take_up_deg, contact_relative_rate_deg_s, overtake_deg_s, reversal_deg_s.
nlohmann::ordered_json take_up_move_json(const TakeUpMove& move);

/// The motor rate (deg/s) of `drive` (position mode: command deg → motor deg, the same transfer
/// maps command rate to motor rate) under slot velocities held for `grid_s` each from t = 0,
/// sampled every `sample_time_s` (an integer fraction of grid_s) up to `duration_s`.
std::vector<double> drive_rate_response(const lti::ProcessModel& drive, const std::vector<double>& slot_velocity_deg_s,
                                        double grid_s, double sample_time_s, double duration_s);

}  // namespace clearshape::study
