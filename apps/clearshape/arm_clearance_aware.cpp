// `clearshape arm move --shaper clearance-aware` (arm_options.hpp): the library's
// design_clearance_aware_move (arm/clearance_aware.hpp, docs/arm.md §7) on the move the options
// describe, its shaper applied to every joint, and the design's summary.
#include <chrono>
#include <sstream>

#include <fmt/format.h>

#include "arm_options.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::cli {

std::vector<Eigen::VectorXd> parse_start_places(const std::string& text, const arm::ArmModel& arm) {
  const std::string allowed = fmt::format("; allowed: start places separated by ';', each {} values φ/β in "
                                          "[-1, 1] (one per joint, the link's place in its play) separated by ','",
                                          arm.dof());
  std::vector<Eigen::VectorXd> places;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ';');) {
    Eigen::VectorXd f;
    try {
      f = parse_angles(item, "--start-places", arm);
    } catch (const InvalidArgument&) {
      throw InvalidArgument(fmt::format("--start-places = '{}': '{}' is not a start place{}", text, item, allowed));
    }
    for (Eigen::Index i = 0; i < f.size(); ++i) {
      if (f(i) < -1.0 || f(i) > 1.0) {
        throw InvalidArgument(fmt::format("--start-places = '{}': {} is outside [-1, 1]{}", text, f(i), allowed));
      }
    }
    places.push_back(f);
  }
  if (places.empty()) throw InvalidArgument(fmt::format("--start-places = '{}'{}", text, allowed));
  return places;
}

arm::ArmClearanceAwareOptions clearance_aware_options(const arm::ArmModel& arm, const MoveRequest& m) {
  arm::ArmClearanceAwareOptions o;
  o.play.limits = joint_limits(arm, m);
  o.play.sample_time_s = m.sample_time_s;
  o.play.settle_s = m.design_settle_s;
  o.play.flank_margin = m.flank_margin;  // the design plays the move planned within the same lowered limits
  o.play.flank_floor = m.flank_floor;
  o.slots = m.slots;
  o.grid_s = m.grid_s;
  if (!m.start_places.empty()) o.start_places = parse_start_places(m.start_places, arm);
  o.max_evaluations = m.evaluations;
  o.threads = m.threads;
  return o;
}

namespace {

std::string design_summary(const arm::ArmClearanceAwareResult& d, double seconds) {
  std::string s = fmt::format("shaper      clearance-aware on every joint: {} impulses, {:.4f} s\n",
                              d.shaper.size(), d.shaper.duration_s());
  std::string impulses;
  for (const shaping::Impulse& i : d.shaper.impulses()) {
    impulses += fmt::format("{}{:.17g}:{:.17g}", impulses.empty() ? "" : ",", i.time_s, i.amplitude);
  }
  s += "impulses    " + impulses + "\n";
  for (std::size_t p = 0; p < d.start_places.size(); ++p) {
    s += fmt::format("start place {}: tool residual {:.5f} mm unshaped, {:.5f} mm shaped\n",
                     format_angles(d.start_places[p]), 1e3 * d.unshaped_residual_m[p], 1e3 * d.shaped_residual_m[p]);
  }
  s += fmt::format("design      worst ratio to unshaped {:.4f} over {} start places, {} evaluations, {:.2f} s\n",
                   d.worst_ratio, d.start_places.size(), d.evaluations, seconds);
  if (d.worse_than_unshaped) {
    s += "WARNING     the design leaves MORE tool residual than unshaped from some start place (WORSE than "
         "unshaped); more --evaluations or other --slots/--grid-s may help\n";
  }
  return s;
}

}  // namespace

arm::JointTrajectory clearance_aware_move(const arm::ArmModel& arm, const MoveRequest& m,
                                          const arm::JointTrajectory& unshaped, std::string& summary,
                                          std::vector<shaping::Shaper>& applied) {
  const arm::ArmClearanceAwareOptions options = clearance_aware_options(arm, m);
  const arm::PointToPoint move{parse_angles(m.from, "--from", arm), parse_angles(m.to, "--to", arm)};
  const auto start = std::chrono::steady_clock::now();
  const arm::ArmClearanceAwareResult d = arm::design_clearance_aware_move(arm, move, options);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary += design_summary(d, seconds);
  applied.assign(static_cast<std::size_t>(arm.dof()), d.shaper);
  return arm::shape_trajectory(unshaped, applied);
}

}  // namespace clearshape::cli
