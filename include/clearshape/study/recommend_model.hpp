#pragma once
// `clearshape recommend --model FIT.json --move …` (docs/recommend.md; Python: clearshape.recommend):
// each candidate's predicted
// Eq. 5.1 mean deviation on the identified nonlinear model (drive + play + contact law, thesis
// §4.2) for the user's move, beside Klipper's measure; and the tie rule that uses it.
#include <optional>
#include <string>
#include <vector>

#include "clearshape/advise/recommend.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::study {

struct MovePrediction {
  std::string signal_name;            ///< link_angle_deg (position) or link_rate_deg_s (speed)
  std::string move, move_parameters;  ///< the signal type and its parameters (JSON text), for the output
  double duration_s = 0.0;
  double sample_time_s = 1e-3;
  double initial_play_fraction = 0.0;
  double unshaped_md = 0.0;           ///< "none"
  /// One per candidate of the recommendation (nullopt: the candidate is unavailable).
  std::vector<std::optional<double>> md;
};

/// Simulates `model` under the move (sampled at 1/sample_time_s over duration_s), unshaped and
/// through each available candidate (shaping::shape_offline, the record's length kept), with
/// simulate_command (the mode's command path), and computes Eq. 5.1
/// (metrics::mean_deviation, default options — as `clearshape simulate` reports it) on the link
/// angle in position mode, the link rate in speed mode. Throws InvalidArgument for a move that does
/// not start from rest at 0 after t = 0 or never moves, RuntimeError if a simulation fails.
MovePrediction predict_mean_deviations(const ClearanceModel& model, const signal::Signal& move,
                                       double duration_s, double sample_time_s, double initial_play_fraction,
                                       const advise::Recommendation& recommendation);

/// Eq. 5.1 on `model` of the move shaped by `shaper`, sampled as `prediction` was: the number
/// predict_mean_deviations gives a candidate with that shaper.
double predict_shaped_md(const ClearanceModel& model, const signal::Signal& move, const MovePrediction& prediction,
                         const shaping::Shaper& shaper);

/// The tie rule: among the candidates the recommendation's rule ties (available, inside the
/// budget, worst-case remaining vibration within `vibration_tolerance` of the least of those),
/// the one with the least predicted MD wins (predicted MDs within 1 % of each other: the shorter).
/// Updates `chosen` and appends the reason. No change when nothing was chosen.
void apply_predicted_md(advise::Recommendation& recommendation, const MovePrediction& prediction,
                        double vibration_tolerance);

}  // namespace clearshape::study
