// The arm study (arm/study.hpp; docs/arm.md, "The arm study"): the benchmark of every design, the
// mode map over a grid of poses, results.json and tables.md.
#include "clearshape/arm/study.hpp"

#include <cmath>
#include <numbers>

#include <fmt/format.h>
#include <kdl/chain.hpp>

#include "chain_data.hpp"
#include "clearshape/arm/modes.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/parallel.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"

namespace clearshape::arm {

namespace {

MoveShaping shaping_of(const ArmStudySpec& spec, const std::string& design) {
  MoveShaping s;
  s.schedule = design == "unshaped" || design == "flank-unshaped" ? ShaperSchedule::none
               : design == "fixed"                                 ? ShaperSchedule::fixed
                                                                   : ShaperSchedule::end_pose;
  s.method = spec.method;
  s.every_mode = spec.every_mode;
  return s;
}

MovePlayOptions play_options(const ArmStudySpec& spec, int dof) {
  MovePlayOptions o;
  for (int i = 0; i < dof; ++i) o.limits.push_back(spec.limits[spec.limits.size() == 1 ? 0 : static_cast<std::size_t>(i)]);
  o.sample_time_s = spec.sample_time_s;
  o.settle_s = spec.settle_s;
  return o;
}

// The grid of the map: `points` angles over each of the first two joints' ranges (a continuous
// joint: ±π), the other joints at the workspace centre.
std::vector<std::vector<double>> map_axes(const ArmModel& arm, int points) {
  std::vector<std::vector<double>> axes;
  for (int i = 0; i < std::min(arm.dof(), 2); ++i) {
    const ChainJoint& j = arm.chain.joints()[static_cast<std::size_t>(i)];
    const double lo = j.limited ? j.lower_rad : -std::numbers::pi, hi = j.limited ? j.upper_rad : std::numbers::pi;
    std::vector<double> a;
    for (int k = 0; k < points; ++k) a.push_back(lo + (hi - lo) * k / (points - 1));
    axes.push_back(a);
  }
  return axes;
}

nlohmann::ordered_json modes_at(const ArmModel& arm, ChainWorkspace& ws, const Eigen::VectorXd& pose) {
  const ArmModes m = joint_modes(arm, pose);
  nlohmann::ordered_json p;
  p["pose_rad"] = std::vector<double>(pose.data(), pose.data() + pose.size());
  const Eigen::Vector3d tool = ws.tip_position_m(pose);
  p["tool_m"] = {tool.x(), tool.y(), tool.z()};
  std::vector<double> f_hz, zeta;
  for (Eigen::Index k = 0; k < m.natural_frequency_rad_s.size(); ++k) {
    f_hz.push_back(m.natural_frequency_rad_s(k) / (2.0 * std::numbers::pi));
    zeta.push_back(m.damping_ratio(k));
  }
  p["natural_frequency_hz"] = f_hz;
  p["damping_ratio"] = zeta;
  p["dominant_mode"] = m.dominant_mode;
  return p;
}

nlohmann::ordered_json mode_map(const ArmModel& arm, int points) {
  const auto axes = map_axes(arm, points);
  ChainWorkspace ws(arm.chain);
  nlohmann::ordered_json map;
  map["source"] = "linearised: arm::joint_modes at every pose (every play closed on a flank)";
  map["joints"] = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < axes.size(); ++i) {
    map["joints"].push_back({{"name", arm.joints[i].name}, {"angles_rad", axes[i]}});
  }
  map["poses"] = nlohmann::ordered_json::array();
  Eigen::VectorXd pose = workspace_centre(arm);
  const std::size_t second = axes.size() > 1 ? axes[1].size() : 1;
  for (std::size_t a = 0; a < axes[0].size(); ++a) {  // row-major: the first joint's angle outer
    for (std::size_t b = 0; b < second; ++b) {
      pose(0) = axes[0][a];
      if (axes.size() > 1) pose(1) = axes[1][b];
      map["poses"].push_back(modes_at(arm, ws, pose));
    }
  }
  return map;
}

nlohmann::ordered_json drawing(const ArmModel& arm) {
  const Eigen::VectorXd centre = workspace_centre(arm);
  nlohmann::ordered_json d;
  d["pose_rad"] = std::vector<double>(centre.data(), centre.data() + centre.size());
  d["points_m"] = nlohmann::ordered_json::array();
  for (const Eigen::Vector3d& p : arm_points_m(arm, centre)) d["points_m"].push_back({p.x(), p.y(), p.z()});
  return d;
}

}  // namespace

std::vector<Eigen::Vector3d> arm_points_m(const ArmModel& arm, const Eigen::VectorXd& pose_rad) {
  const RigidChain::Data& d = arm.chain.data();
  if (pose_rad.size() != arm.dof()) throw_invalid("arm_points_m: pose size", static_cast<double>(pose_rad.size()), "one per joint");
  std::vector<Eigen::Vector3d> out{Eigen::Vector3d::Zero()};
  KDL::Frame frame = KDL::Frame::Identity();  // F_i = F_{i−1} · pose_i(q_i): segment i ends at joint i's child link
  for (unsigned s = 0; s < d.chain.getNrOfSegments(); ++s) {
    frame = frame * d.chain.getSegment(s).pose(pose_rad(static_cast<Eigen::Index>(s)));
    out.emplace_back(frame.p.x(), frame.p.y(), frame.p.z());
  }
  const KDL::Vector tool = frame * d.tip_offset.p;
  out.emplace_back(tool.x(), tool.y(), tool.z());
  return out;
}

ArmStudyResult run_arm_study(const ArmStudySpec& spec, const ArmModel& arm) {
  ArmStudyResult r;
  r.moves = pick_and_place_moves(arm, spec.moves, spec.seed, spec.margin);
  const MovePlayOptions play = play_options(spec, arm.dof());
  MovePlayOptions flank_play = play;  // the flank designs: the move re-planned within flank_keeping_limits
  flank_play.flank_margin = spec.flank_margin;
  flank_play.flank_floor = spec.flank_floor;
  std::vector<std::string> names{"unshaped"};
  names.insert(names.end(), spec.designs.begin(), spec.designs.end());
  const std::size_t n_moves = r.moves.size();
  for (const std::string& n : names) {
    r.designs.push_back({n, shaping_of(spec, n), std::vector<MovePlay>(n_moves), 0.0, 0.0});
  }
  const auto ca = std::find(names.begin(), names.end(), "clearance-aware");
  const std::size_t ca_index = static_cast<std::size_t>(ca - names.begin());
  if (ca != names.end()) r.clearance_aware.resize(n_moves);
  ArmClearanceAwareOptions ca_options;
  ca_options.play = play;
  ca_options.slots = spec.slots;
  ca_options.max_evaluations = spec.evaluations;
  ca_options.threads = 1;  // the moves run in parallel instead
  // The clearance-aware tasks (the long ones) first, then the rest: task k → (design, move).
  std::vector<std::pair<std::size_t, std::size_t>> tasks;
  if (ca != names.end()) {
    for (std::size_t m = 0; m < n_moves; ++m) tasks.emplace_back(ca_index, m);
  }
  for (std::size_t d = 0; d < names.size(); ++d) {
    for (std::size_t m = 0; m < n_moves && d != ca_index; ++m) tasks.emplace_back(d, m);
  }
  parallel_for(tasks.size(), spec.threads, [&](std::size_t k) {
    const auto [d, m] = tasks[k];
    if (d == ca_index) {
      r.clearance_aware[m] = design_clearance_aware_move(arm, r.moves[m], ca_options);
      const std::vector<shaping::Shaper> shapers(static_cast<std::size_t>(arm.dof()), r.clearance_aware[m].shaper);
      r.designs[d].moves[m] = play_move_with(arm, r.moves[m], shapers, play);
    } else {
      const bool flank = names[d].starts_with("flank-");
      r.designs[d].moves[m] = play_move(arm, r.moves[m], r.designs[d].shaping, flank ? flank_play : play);
    }
  });
  for (BenchmarkDesign& b : r.designs) {
    for (const MovePlay& p : b.moves) b.total_residual_m += p.residual_m;
  }
  const double reference = r.designs.front().total_residual_m;
  for (BenchmarkDesign& b : r.designs) b.improvement = reference > 0.0 ? 1.0 - b.total_residual_m / reference : 0.0;
  r.mode_map = mode_map(arm, spec.map_points);
  r.drawing = drawing(arm);
  return r;
}

}  // namespace clearshape::arm
