// The clearance-aware shaper of a study (study/clearance_aware.hpp): designed once, before the
// simulated tests and the rig tests that use it, on the study's fitted clearance model. The
// take-up profile of a rig table (study/take_up.hpp): designed per table, for its input's move.
#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/study/clearance_aware.hpp"
#include "clearshape/study/take_up.hpp"
#include "context.hpp"

namespace clearshape::study::detail {

namespace {

bool wanted(const Protocol& p) {
  for (const auto& t : p.rig_tests.tables) {
    for (const auto& col : t.columns) {
      if (col.shaper == kClearanceAwareShaper) return true;
    }
  }
  const auto& s = p.simulation.shapers;
  const auto& m = p.simulation.mode_sources;
  return std::find(s.begin(), s.end(), kClearanceAwareShaper) != s.end() &&
         std::find(m.begin(), m.end(), "clearance-model") != m.end();
}

// The inputs the clearance-aware shaper runs on (its rig-test tables; else every step and
// double step), each as its own command profile (design_move).
std::vector<DesignMove> moves_of(const Protocol& p) {
  std::set<std::string> used;
  for (const auto& t : p.rig_tests.tables) {
    for (const auto& col : t.columns) {
      if (col.shaper == kClearanceAwareShaper) used.insert(t.input);
    }
  }
  std::vector<DesignMove> moves;
  for (const auto& in : p.inputs) {
    const bool kind = in.signal.get_if<signal::Step>() != nullptr || in.signal.get_if<signal::DoubleStep>() != nullptr;
    if (!kind || (!used.empty() && used.count(in.name) == 0)) continue;
    // Position mode: cut whole 30 Hz updates (§3.2) so the pulse path meets the move as on the rig.
    const double update_s = p.mode == rig::CommandMode::position ? signal::PulseTrainConfig{}.update_period_s() : 0.0;
    auto m = design_move(in.name, in.signal, p.sample_rate_hz, p.record_s, update_s);
    if (!m) continue;  // no motion
    moves.push_back(std::move(*m));
  }
  return moves;
}

}  // namespace

void ensure_clearance_aware(Context& c) {
  if (c.clearance_aware_tried || !wanted(c.p)) return;
  c.clearance_aware_tried = true;
  if (!c.model) {
    c.clearance_aware_note = "no fitted clearance model (stage 3 did not run)";
    return;
  }
  if (!c.link_mode.available) {
    c.clearance_aware_note = "no link mode: the duration bound is ZVDD's for the link mode";
    return;
  }
  ClearanceAwareRequest r;
  r.model = *c.model;
  r.profiles = moves_of(c.p);
  if (r.profiles.empty()) {
    c.clearance_aware_note = "no step or double-step input to design for";
    return;
  }
  for (const auto& m : r.profiles) r.moves.push_back(m.command.values.back());
  shaping::DesignRequest zvdd;
  zvdd.method = shaping::Method::zvdd;
  zvdd.mode = c.link_mode.mode;
  r.max_duration_s = c.p.shaping.clearance_aware_max_duration_s > 0.0 ? c.p.shaping.clearance_aware_max_duration_s
                                                                       : std::min(5.0, shaping::design(zvdd).duration_s());
  if (c.p.shaping.grid_hz > 0.0) r.grid_s = 1.0 / c.p.shaping.grid_hz;
  r.sample_time_s = c.p.sample_time_s();
  // Every start place at the fitted model, its ±1σ corners and the flank damping's run spread
  // (design_uncertainty; docs/worn-coupling.md).
  if (c.model_sigma) r.uncertainty = design_uncertainty(*c.model_sigma);
  r.max_evaluations = c.p.quick ? std::min(40, c.p.shaping.clearance_aware_max_evaluations)
                                : c.p.shaping.clearance_aware_max_evaluations;
  r.threads = c.threads;
  try {
    const ClearanceAwareResult d = design_clearance_aware(r);
    c.clearance_aware = d.shaper;
    c.clearance_aware_note = fmt::format(
        "designed on the fitted clearance model (play {:.4g} deg, K {:.4g}, n {:.3g}, {} {:.4g}, Coulomb {:.3g} N·m) "
        "for moves {} from {} start places × model points, bound {:.4g} s ({}); worst case keeps {:.3g} % "
        "of its unshaped MD on the model (worst MD {:.4g} deg, unshaped {:.4g}){}; {} evaluations, {}",
        r.model.play_rad * 180.0 / M_PI, r.model.stiffness, r.model.exponent,
        r.model.contact_law == ContactLawChoice::flores ? "Flores e" : "D",
        r.model.contact_law == ContactLawChoice::flores ? r.model.restitution : r.model.damping, r.model.coulomb_n_m,
        fmt::join(r.moves, "/"), r.uncertainty.size(), r.max_duration_s,
        c.p.shaping.clearance_aware_max_duration_s > 0.0 ? "the protocol's" : "ZVDD, link mode", 100.0 * d.worst_ratio, d.worst_md_deg,
        d.worst_unshaped_md_deg, d.worse_than_unshaped ? " — WORSE than unshaped in some case" : "", d.evaluations,
        d.termination);
    json impulses = json::array();
    for (const auto& i : d.shaper.impulses()) impulses.push_back({{"time_s", i.time_s}, {"amplitude", i.amplitude}});
    json cases = json::array();
    for (const auto& k : d.cases) {
      cases.push_back({{"move", k.move},
                       {"input", k.move_name},
                       {"play_factor", k.point.play_factor},
                       {"stiffness_factor", k.point.stiffness_factor},
                       {"coulomb_factor", k.point.coulomb_factor},
                       {"damping_factor", k.point.damping_factor},
                       {"initial_play_fraction", k.point.initial_play_fraction},
                       {"md_unshaped_deg", k.md_unshaped_deg},
                       {"md_shaped_deg", k.md_shaped_deg}});
    }
    c.sections["clearance_aware"] = {{"moves", r.moves},
                                     {"max_duration_s", r.max_duration_s},
                                     {"impulses", impulses},
                                     {"duration_s", d.shaper.duration_s()},
                                     {"objective", d.objective},
                                     {"worst_md_deg", d.worst_md_deg},
                                     {"worst_unshaped_md_deg", d.worst_unshaped_md_deg},
                                     {"worst_ratio", d.worst_ratio},
                                     {"worse_than_unshaped", d.worse_than_unshaped},
                                     {"evaluations", d.evaluations},
                                     {"termination", d.termination},
                                     {"cases", cases}};
    c.log("clearance-aware: " + c.clearance_aware_note);
  } catch (const std::exception& e) {
    c.clearance_aware_note = fmt::format("design failed: {}", e.what());
    c.log("clearance-aware: " + c.clearance_aware_note);
  }
}

std::optional<shaping::Shaper> take_up_for(Context& c, const InputSpec& in, std::string& reason) {
  if (!c.model) {
    reason = "no fitted clearance model (stage 3 did not run)";
    return std::nullopt;
  }
  if (!c.link_mode.available) {
    reason = "no link mode: the duration bound is ZVDD's for the link mode";
    return std::nullopt;
  }
  TakeUpRequest r;
  r.model = *c.model;
  double rise_s = 0.0;
  if (const auto* s = in.signal.get_if<signal::Step>()) {
    r.moves = {s->amplitude};
    rise_s = s->rise_s;
  } else if (const auto* d = in.signal.get_if<signal::DoubleStep>()) {
    r.moves = {d->amplitude};  // both steps take this profile (the shaper is one per input)
    rise_s = d->rise_s;
  } else {
    reason = "take-up is designed for step and double-step inputs";
    return std::nullopt;
  }
  if (c.p.shaping.grid_hz > 0.0) r.grid_s = 1.0 / c.p.shaping.grid_hz;
  shaping::DesignRequest zvdd;
  zvdd.method = shaping::Method::zvdd;
  zvdd.mode = c.link_mode.mode;
  // ZVDD's added delay as the rig runs it: its last impulse on the update grid.
  r.max_duration_s = std::min(5.0, std::round(shaping::design(zvdd).duration_s() / r.grid_s) * r.grid_s);
  try {
    const TakeUpResult d = design_take_up(r);
    const TakeUpMove& m = d.moves.front();
    const bool smeared = rise_s > r.grid_s + 1e-9;
    reason = fmt::format(
        "take-up for {:g} deg on the fitted clearance model (play {:.4g} deg, Coulomb {:.3g} N·m): slots {:.4g} deg/s; "
        "link leaves the rear flank at {:.4f} s, meets the braking flank at {:.4f} s{}",
        m.move_deg, r.model.play_rad * 180.0 / M_PI, r.model.coulomb_n_m, fmt::join(m.slot_velocity_deg_s, "/"),
        m.separation_s, m.contact_s,
        smeared ? fmt::format("; the input's {:g} s rise spreads the profile over more updates (no longer a take-up)",
                              rise_s)
                : "");
    json section = take_up_move_json(m);
    section["max_duration_s"] = r.max_duration_s;
    section["coulomb_n_m"] = r.model.coulomb_n_m;
    section["flank_keeping_deceleration_rad_s2"] = d.flank_keeping_deceleration_rad_s2;
    section["flank_keeping_move_time_s"] = d.flank_keeping_move_time_s.front();
    section["input_rise_s"] = rise_s;
    c.sections["take_up"][in.name] = section;
    c.log("take-up: " + reason);
    return m.shaper;
  } catch (const std::exception& e) {
    reason = fmt::format("take-up design failed: {}", e.what());
    c.log(reason);
    return std::nullopt;
  }
}

}  // namespace clearshape::study::detail
