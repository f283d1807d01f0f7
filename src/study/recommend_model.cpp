#include "clearshape/study/recommend_model.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "clearshape/shaping/apply.hpp"

namespace clearshape::study {
namespace {

// Eq. 5.1 (thesis §5.1.2) of the signal the study measures in the model's mode.
double md_of(const ClearanceModel& model, const UniformSeries& command, double duration_s,
             double initial_play_fraction) {
  const ModelResponse r = simulate_command(model, command, duration_s, initial_play_fraction);
  const bool position = model.mode == rig::CommandMode::position;
  const UniformSeries s{0.0, r.sample_time_s, position ? r.link_angle_deg : r.link_rate_deg_s};
  return metrics::mean_deviation(s).mean_deviation;
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char ch) { return static_cast<char>(std::toupper(ch)); });
  return s;
}

}  // namespace

MovePrediction predict_mean_deviations(const ClearanceModel& model, const signal::Signal& move,
                                       double duration_s, double sample_time_s, double initial_play_fraction,
                                       const advise::Recommendation& recommendation) {
  MovePrediction p;
  p.signal_name = model.mode == rig::CommandMode::position ? "link_angle_deg" : "link_rate_deg_s";
  p.duration_s = duration_s;
  p.sample_time_s = sample_time_s;
  p.initial_play_fraction = initial_play_fraction;
  const UniformSeries command = signal::sample(move, 1.0 / sample_time_s, duration_s);
  // The model starts at rest at the command's first value: a move at t = 0 would not be simulated.
  if (command.values.empty() || command.values.front() != 0.0) {
    throw InvalidArgument(fmt::format("--move: the command is {} at t = 0, where the model starts at rest; start the move later "
                                      "(--start-s > 0, e.g. 0.2)", command.values.empty() ? 0.0 : command.values.front()));
  }
  if (std::all_of(command.values.begin(), command.values.end(), [](double v) { return v == 0.0; })) {
    throw InvalidArgument("--move: the command never leaves 0 within --move-duration-s; give --amplitude and a --start-s inside it");
  }
  p.unshaped_md = md_of(model, command, duration_s, initial_play_fraction);
  for (const auto& c : recommendation.candidates) {
    if (!c.available || !c.shaper) {
      p.md.emplace_back();
      continue;
    }
    p.md.emplace_back(md_of(model, shaping::shape_offline(*c.shaper, command, false), duration_s, initial_play_fraction));
  }
  return p;
}

double predict_shaped_md(const ClearanceModel& model, const signal::Signal& move, const MovePrediction& p,
                         const shaping::Shaper& shaper) {
  const UniformSeries command = signal::sample(move, 1.0 / p.sample_time_s, p.duration_s);
  return md_of(model, shaping::shape_offline(shaper, command, false), p.duration_s, p.initial_play_fraction);
}

void apply_predicted_md(advise::Recommendation& r, const MovePrediction& p, double vibration_tolerance) {
  if (!r.chosen) return;
  const auto& c = r.candidates;
  std::optional<std::size_t> least;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (c[i].available && c[i].within_budget && !c[i].duplicate_of && (!least || c[i].remaining_worst < c[*least].remaining_worst)) {
      least = i;
    }
  }
  const double limit = c[*least].remaining_worst + vibration_tolerance;
  std::vector<std::size_t> tied;
  for (std::size_t i = 0; i < c.size(); ++i) {
    // Never a candidate the model says leaves more than unshaped (issue 19).
    if (c[i].available && c[i].within_budget && !c[i].duplicate_of && c[i].remaining_worst <= limit && p.md[i] &&
        *p.md[i] <= p.unshaped_md) {
      tied.push_back(i);
    }
  }
  const std::size_t rule_pick = *r.chosen;
  // Shortest first; a longer candidate wins only with a predicted MD more than 1 % below.
  std::stable_sort(tied.begin(), tied.end(), [&](std::size_t a, std::size_t b) { return c[a].duration_s < c[b].duration_s; });
  std::size_t best = tied.empty() ? rule_pick : tied.front();
  for (const std::size_t i : tied) {
    if (*p.md[i] < 0.99 * *p.md[best]) best = i;
  }
  r.chosen = best;
  if (p.md[best] && *p.md[best] > p.unshaped_md) {
    r.warning += fmt::format("{}on the model every tied candidate leaves more than unshaped for the move ({} {:.4g} > "
                             "{:.4g}): do not shape this move with it",
                             r.warning.empty() ? "" : "; ", upper(c[best].name), *p.md[best], p.unshaped_md);
  }
  if (best == rule_pick) {
    r.reason += fmt::format("; on the model it leaves the least predicted Eq. 5.1 MD of the {} tied candidate(s) ({:.4g}, unshaped {:.4g})",
                            tied.size(), *p.md[best], p.unshaped_md);
  } else {
    r.reason = fmt::format("{}: of the {} candidates within {:.1f} points of the least worst-case remaining vibration, the least predicted "
                           "Eq. 5.1 MD on the model for the move ({:.4g}, unshaped {:.4g}; {} by the delay rule: {:.4g}, {:.1f} ms shorter)",
                           upper(c[best].name), tied.size(), 100.0 * vibration_tolerance, *p.md[best], p.unshaped_md,
                           upper(c[rule_pick].name), *p.md[rule_pick], 1000.0 * (c[best].duration_s - c[rule_pick].duration_s));
  }
}

}  // namespace clearshape::study
