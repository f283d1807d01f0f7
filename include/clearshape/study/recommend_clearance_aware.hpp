#pragma once
// `clearshape recommend --model FIT.json --move step … --clearance-aware` (docs/recommend.md): the
// clearance-aware shaper (study/clearance_aware.hpp), designed by simulation on the identified
// nonlinear model for the move's step amplitude, offered beside the linear candidates with its
// predicted Eq. 5.1 MD for the move (computed as theirs: recommend_model.hpp).
#include <string>

#include "clearshape/advise/recommend.hpp"
#include "clearshape/shaping/shaper.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/study/model.hpp"
#include "clearshape/study/recommend_model.hpp"

namespace clearshape::study {

struct ClearanceAwareCandidate {
  shaping::Shaper shaper{"clearance-aware", {{0.0, 1.0}}};
  double max_duration_s = 0.0;       ///< the design's bound: ZVDD's duration for the first mode, or the delay budget
  std::string bound_source;
  double predicted_md = 0.0;         ///< Eq. 5.1 on the model for the move, as the other candidates'
  double design_worst_md_deg = 0.0;  ///< the design objective's worst case over the uncertainty set
  int evaluations = 0;
  double design_time_s = 0.0;
};

/// Designs for the move (a step: its amplitude, start and rise) on `model`, bounded by the ZVDD
/// duration for the recommendation's first mode, or by `max_delay_s` when that is shorter.
/// Throws InvalidArgument if the move is not a step or there is no mode; RuntimeError if the
/// design fails.
ClearanceAwareCandidate design_for_move(const ClearanceModel& model, const signal::Signal& move,
                                        const MovePrediction& prediction, const advise::Recommendation& recommendation,
                                        double max_delay_s);

}  // namespace clearshape::study
