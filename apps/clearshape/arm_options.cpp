// Options shared by the `clearshape arm` subcommands (arm_options.hpp).
#include "arm_options.hpp"

#include <cmath>
#include <sstream>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::cli {

void add_arm_options(CLI::App& app, ArmSource& source) {
  const auto names = arm::builtin_arm_names();
  auto* builtin = app.add_option("--arm", source.name, "A built-in arm: " + fmt::format("{}", fmt::join(names, ", ")))
                      ->check(CLI::IsMember(names))
                      ->capture_default_str();
  auto* urdf = app.add_option("--urdf", source.urdf, "Your arm's URDF (with --config; docs/arm.md §4)")
                   ->check(CLI::ExistingFile);
  auto* config = app.add_option("--config", source.config, "Your arm's TOML: drives, gears, play per joint (with --urdf)")
                     ->check(CLI::ExistingFile);
  urdf->needs(config);
  config->needs(urdf);
  builtin->excludes(urdf);
  source.play_option = app.add_option("--play-deg", source.play_deg,
                                      "Total play of every joint (deg, 0-10), replacing the arm's own")
                           ->check(CLI::Range(0.0, 10.0));
}

CLI::App* add_arm_subcommand(CLI::App& parent, const std::string& name, const std::string& description,
                             ArmSource& source) {
  CLI::App* sub = parent.add_subcommand(name, description);
  add_arm_options(*sub, source);
  return sub;
}

arm::ArmModel load_arm(const ArmSource& source) {
  arm::ArmModel model =
      source.urdf.empty() ? arm::builtin_arm(source.name) : arm::load_arm(source.urdf, source.config);
  if (source.play_option != nullptr && source.play_option->count() > 0) {
    for (arm::ArmJoint& j : model.joints) j.half_play_rad = 0.5 * source.play_deg * M_PI / 180.0;
  }
  return model;
}

namespace {

// "a,b,…" → the numbers; `complaint(item)` for an item that is not a finite number.
template <class Complaint>
std::vector<double> parse_numbers(const std::string& text, const Complaint& complaint) {
  std::vector<double> values;
  std::stringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    std::size_t used = 0;
    double v = NAN;
    try {
      v = std::stod(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || item.find_first_not_of(" \t", used) != std::string::npos || !std::isfinite(v)) complaint(item);
    values.push_back(v);
  }
  return values;
}

std::string joint_names(const arm::ArmModel& arm) {
  std::string joints;
  for (const auto& j : arm.joints) joints += (joints.empty() ? "" : ", ") + j.name;
  return joints;
}

}  // namespace

Eigen::VectorXd parse_angles(const std::string& text, const std::string& option, const arm::ArmModel& arm) {
  const std::string allowed = fmt::format("; allowed: {} comma-separated finite angles in rad (joints: {})",
                                          arm.dof(), joint_names(arm));
  const std::vector<double> values = parse_numbers(text, [&](const std::string& item) {
    throw InvalidArgument(fmt::format("{} = '{}': '{}' is not an angle{}", option, text, item, allowed));
  });
  if (values.size() != static_cast<std::size_t>(arm.dof())) {
    throw InvalidArgument(fmt::format("{} = '{}' has {} angles{}", option, text, values.size(), allowed));
  }
  return Eigen::Map<const Eigen::VectorXd>(values.data(), arm.dof());
}

std::vector<double> parse_joint_values(const std::string& text, const std::string& option, const arm::ArmModel& arm,
                                       const std::string& unit, double lo, double hi) {
  const std::string allowed = fmt::format("; allowed: one value for every joint or {} comma-separated, each in "
                                          "[{:g}, {:g}] {} (joints: {})",
                                          arm.dof(), lo, hi, unit, joint_names(arm));
  std::vector<double> values = parse_numbers(text, [&](const std::string& item) {
    throw InvalidArgument(fmt::format("{} = '{}': '{}' is not a number{}", option, text, item, allowed));
  });
  if (values.size() == 1) values.assign(static_cast<std::size_t>(arm.dof()), values.front());
  if (values.size() != static_cast<std::size_t>(arm.dof())) {
    throw InvalidArgument(fmt::format("{} = '{}' has {} values{}", option, text, values.size(), allowed));
  }
  for (const double v : values) {
    if (!(v >= lo && v <= hi)) throw InvalidArgument(fmt::format("{} = '{}': {:g} is out of range{}", option, text, v, allowed));
  }
  return values;
}

std::string format_angles(const Eigen::VectorXd& q) {
  std::string s;
  for (Eigen::Index i = 0; i < q.size(); ++i) s += fmt::format("{}{:.4g}", i == 0 ? "" : ", ", q(i));
  return "(" + s + ")";
}

std::string output_kind(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (ext != ".json" && ext != ".csv") {
    throw InvalidArgument(fmt::format("-o = '{}': allowed a file name ending in .json or .csv", path.string()));
  }
  return ext;
}

}  // namespace clearshape::cli
