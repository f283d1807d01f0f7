// The clearance-aware shaper of a study (study/clearance_aware.hpp): designed once, before the
// simulated tests and the rig tests that use it, on the study's fitted clearance model.
#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/study/clearance_aware.hpp"
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

// The moves: the amplitudes of the protocol's steps and double steps (both steps), by size.
std::vector<double> moves_of(const Protocol& p) {
  std::set<double> moves;
  for (const auto& in : p.inputs) {
    if (const auto* s = in.signal.get_if<signal::Step>()) moves.insert(s->amplitude);
    if (const auto* d = in.signal.get_if<signal::DoubleStep>()) {
      moves.insert(d->amplitude);
      moves.insert(d->second_amplitude);
    }
  }
  return {moves.begin(), moves.end()};
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
  r.moves = moves_of(c.p);
  shaping::DesignRequest zvdd;
  zvdd.method = shaping::Method::zvdd;
  zvdd.mode = c.link_mode.mode;
  r.max_duration_s = std::min(5.0, shaping::design(zvdd).duration_s());
  if (c.p.shaping.grid_hz > 0.0) r.grid_s = 1.0 / c.p.shaping.grid_hz;
  r.sample_time_s = c.p.sample_time_s();
  r.max_evaluations = c.p.quick ? 20 : 80;
  r.threads = c.threads;
  try {
    const ClearanceAwareResult d = design_clearance_aware(r);
    c.clearance_aware = d.shaper;
    c.clearance_aware_note = fmt::format(
        "designed on the fitted clearance model (play {:.4g} deg, K {:.4g}, n {:.3g}, D {:.4g}) for moves {} "
        "and {} uncertainty points, bound {:.4g} s (ZVDD, link mode); worst model MD {:.4g} deg (unshaped "
        "{:.4g}); {} evaluations, {}",
        r.model.play_rad * 180.0 / M_PI, r.model.stiffness, r.model.exponent, r.model.damping,
        fmt::join(r.moves, "/"), r.uncertainty.size(), r.max_duration_s, d.worst_md_deg, d.worst_unshaped_md_deg,
        d.evaluations, d.termination);
    json impulses = json::array();
    for (const auto& i : d.shaper.impulses()) impulses.push_back({{"t", i.time_s}, {"a", i.amplitude}});
    json cases = json::array();
    for (const auto& k : d.cases) {
      cases.push_back({{"move", k.move},
                       {"play_factor", k.point.play_factor},
                       {"stiffness_factor", k.point.stiffness_factor},
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
                                     {"evaluations", d.evaluations},
                                     {"termination", d.termination},
                                     {"cases", cases}};
    c.log("clearance-aware: " + c.clearance_aware_note);
  } catch (const std::exception& e) {
    c.clearance_aware_note = fmt::format("design failed: {}", e.what());
    c.log("clearance-aware: " + c.clearance_aware_note);
  }
}

}  // namespace clearshape::study::detail
