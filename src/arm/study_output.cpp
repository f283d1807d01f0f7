// results.json and tables.md of the arm study (arm/study.hpp; docs/arm.md, "The arm study").
#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>

#include "clearshape/arm/study.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"

namespace clearshape::arm {

namespace {

std::vector<double> values(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

// How many moves `b` leaves with more residual than unshaped (the reference) does.
int moves_worse(const ArmStudyResult& r, const BenchmarkDesign& b) {
  int worse = 0;
  for (std::size_t m = 0; m < b.moves.size(); ++m) worse += b.moves[m].residual_m > r.designs.front().moves[m].residual_m ? 1 : 0;
  return worse;
}

nlohmann::ordered_json study_json(const ArmStudySpec& spec, const ArmModel& arm) {
  nlohmann::ordered_json s;
  s["name"] = spec.name;
  s["file"] = std::filesystem::path(spec.file).filename().string();
  s["arm"] = arm.name;
  s["quick"] = spec.quick;
  nlohmann::ordered_json joints = nlohmann::ordered_json::array();
  for (std::size_t i = 0; i < arm.joints.size(); ++i) {
    const signal::AxisLimits& l = spec.limits[spec.limits.size() == 1 ? 0 : i];
    joints.push_back({{"name", arm.joints[i].name},
                      {"play_deg", 2.0 * arm.joints[i].half_play_rad * 180.0 / M_PI},
                      {"velocity_rad_s", l.velocity},
                      {"acceleration_rad_s2", l.acceleration},
                      {"jerk_rad_s3", l.jerk}});
  }
  s["joints"] = joints;
  s["moves"] = spec.moves;
  s["seed"] = spec.seed;
  s["margin"] = spec.margin;
  s["sample_time_s"] = spec.sample_time_s;
  s["settle_s"] = spec.settle_s;
  s["method"] = shaping::to_string(spec.method);
  s["every_mode"] = spec.every_mode;
  s["clearance_aware"] = {{"evaluations", spec.evaluations}, {"slots", spec.slots}};
  s["flank_keeping"] = {{"margin", spec.flank_margin}, {"floor", spec.flank_floor}};
  s["residual"] = "Eq. 5.1 (mean deviation) of each tool coordinate after the command ends, sqrt(MD_x^2 + MD_y^2 + MD_z^2)";
  return s;
}

// The mean and the longest command of a design over the moves (s): the price of a longer move.
std::pair<double, double> command_s(const BenchmarkDesign& b) {
  double sum = 0.0, longest = 0.0;
  for (const MovePlay& p : b.moves) {
    sum += p.command_end_s;
    longest = std::max(longest, p.command_end_s);
  }
  return {b.moves.empty() ? 0.0 : sum / static_cast<double>(b.moves.size()), longest};
}

nlohmann::ordered_json designs_json(const ArmStudyResult& r) {
  nlohmann::ordered_json out = nlohmann::ordered_json::array();
  const BenchmarkDesign& ref = r.designs.front();
  for (const BenchmarkDesign& b : r.designs) {
    const int worse = moves_worse(r, b);
    out.push_back({{"name", b.name},
                   {"total_residual_mm", 1e3 * b.total_residual_m},
                   {"improvement", b.improvement},
                   {"worse_than_unshaped", b.total_residual_m > ref.total_residual_m},
                   {"moves_worse_than_unshaped", worse},
                   {"mean_command_s", command_s(b).first},
                   {"max_command_s", command_s(b).second}});
  }
  return out;
}

nlohmann::ordered_json move_json(const ArmModel& arm, const ArmStudyResult& r, std::size_t m) {
  const PointToPoint& move = r.moves[m];
  const Eigen::Vector3d tool = arm_points_m(arm, move.to_rad).back();
  nlohmann::ordered_json j{{"index", m}, {"from_rad", values(move.from_rad)}, {"to_rad", values(move.to_rad)},
                           {"tool_end_m", {tool.x(), tool.y(), tool.z()}}};
  const double ref = r.designs.front().moves[m].residual_m;
  for (const BenchmarkDesign& b : r.designs) {
    const MovePlay& p = b.moves[m];
    nlohmann::ordered_json d{{"residual_mm", 1e3 * p.residual_m},
                             {"improvement", ref > 0.0 ? nlohmann::ordered_json(1.0 - p.residual_m / ref) : nullptr},
                             {"command_end_s", p.command_end_s},
                             {"shaper_duration_s", p.shaper_duration_s},
                             {"contact_onsets", p.contact_onsets}};
    j["designs"][b.name] = d;
  }
  if (!r.clearance_aware.empty()) {
    const ArmClearanceAwareResult& c = r.clearance_aware[m];
    j["clearance_aware_design"] = {{"evaluations", c.evaluations},
                                   {"worst_ratio", c.worst_ratio},
                                   {"worse_than_unshaped", c.worse_than_unshaped},
                                   {"unshaped_residual_mm", c.unshaped_residual_m},
                                   {"shaped_residual_mm", c.shaped_residual_m}};
    for (auto& v : j["clearance_aware_design"]["unshaped_residual_mm"]) v = 1e3 * v.get<double>();
    for (auto& v : j["clearance_aware_design"]["shaped_residual_mm"]) v = 1e3 * v.get<double>();
  }
  return j;
}

std::string percent(double improvement) { return fmt::format("{:.1f} %", 100.0 * improvement); }

}  // namespace

nlohmann::ordered_json arm_study_json(const ArmStudySpec& spec, const ArmModel& arm, const ArmStudyResult& r) {
  nlohmann::ordered_json doc = io::make_document();
  doc["study"] = study_json(spec, arm);
  doc["designs"] = designs_json(r);
  doc["moves"] = nlohmann::ordered_json::array();
  for (std::size_t m = 0; m < r.moves.size(); ++m) doc["moves"].push_back(move_json(arm, r, m));
  doc["mode_map"] = r.mode_map;
  doc["drawing"] = r.drawing;
  return doc;
}

std::string arm_study_tables(const ArmStudySpec& spec, const ArmStudyResult& r) {
  std::string md = fmt::format("# Arm study {}{}\n\n{} moves (seed {}), residual = Eq. 5.1 on the tool position after "
                               "the command ends, summed over the moves.\n\n",
                               spec.name, spec.quick ? " (quick)" : "", r.moves.size(), spec.seed);
  md += "| design | Σ residual (mm) | removed | moves worse than unshaped | command mean / max (s) |\n|---|---|---|---|---|\n";
  const BenchmarkDesign& ref = r.designs.front();
  for (const BenchmarkDesign& b : r.designs) {
    const int worse = moves_worse(r, b);
    const std::string removed = &b == &ref ? "—"
                                : b.improvement < 0.0 ? percent(b.improvement) + " (WORSE than unshaped)"
                                                      : percent(b.improvement);
    md += fmt::format("| {} | {:.4f} | {} | {} | {:.3f} / {:.3f} |\n", b.name, 1e3 * b.total_residual_m, removed,
                      &b == &ref ? "—" : std::to_string(worse), command_s(b).first, command_s(b).second);
  }
  md += "\n| move | end pose (rad) |";
  for (const BenchmarkDesign& b : r.designs) md += fmt::format(" {} (mm) |", b.name);
  md += "\n|---|---|";
  for (std::size_t k = 0; k < r.designs.size(); ++k) md += "---|";
  md += "\n";
  for (std::size_t m = 0; m < r.moves.size(); ++m) {
    md += fmt::format("| {} | {:.3f} |", m, fmt::join(values(r.moves[m].to_rad), ", "));
    for (const BenchmarkDesign& b : r.designs) md += fmt::format(" {:.4f} |", 1e3 * b.moves[m].residual_m);
    md += "\n";
  }
  return md;
}

void write_arm_study(const std::filesystem::path& folder, const ArmStudySpec& spec, const ArmModel& arm,
                     const ArmStudyResult& result) {
  io::AtomicBatch batch;
  batch.add(folder / "results.json", arm_study_json(spec, arm, result).dump(2) + "\n");
  batch.add(folder / "tables.md", arm_study_tables(spec, result));
  batch.commit();
}

}  // namespace clearshape::arm
