#include "clearshape/study/recommend_clearance_aware.hpp"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/study/clearance_aware.hpp"

namespace clearshape::study {

ClearanceAwareCandidate design_for_move(const ClearanceModel& model, const signal::Signal& move,
                                        const MovePrediction& prediction, const advise::Recommendation& recommendation,
                                        double max_delay_s) {
  const auto* step = move.get_if<signal::Step>();
  if (step == nullptr) {
    throw InvalidArgument(fmt::format("--clearance-aware: the move is a {}; allowed: step (the design is for step amplitudes)",
                                      move.type()));
  }
  if (recommendation.modes.empty()) throw InvalidArgument("--clearance-aware: no mode was found to bound the design's duration");
  ClearanceAwareCandidate out;
  // The bound: ZVDD for the first mode (the design never adds more delay than it), or the budget.
  const auto& mode = recommendation.modes.front();
  shaping::DesignRequest zvdd;
  zvdd.method = shaping::Method::zvdd;
  zvdd.mode = shaping::Mode::from_hz(mode.frequency_hz, mode.damping_ratio);
  out.max_duration_s = shaping::design(zvdd).duration_s();
  out.bound_source = fmt::format("ZVDD for {:.4g} Hz, ζ {:.3g}", mode.frequency_hz, mode.damping_ratio);
  if (max_delay_s < out.max_duration_s) {
    out.max_duration_s = max_delay_s;
    out.bound_source = "--max-delay-s";
  }
  ClearanceAwareRequest request;
  request.model = model;
  request.moves = {step->amplitude};
  request.rise_s = step->rise_s;
  if (step->start_s > 0.0) request.move_start_s = step->start_s;
  request.max_duration_s = out.max_duration_s;
  const auto begin = std::chrono::steady_clock::now();
  const ClearanceAwareResult r = design_clearance_aware(request);
  out.design_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  out.shaper = r.shaper;
  out.design_worst_md_deg = r.worst_md_deg;
  out.evaluations = r.evaluations;
  out.predicted_md = predict_shaped_md(model, move, prediction, r.shaper);
  return out;
}

}  // namespace clearshape::study
