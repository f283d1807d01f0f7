// Joint trajectories as CSV and as JSON in the shape of a ROS trajectory_msgs/JointTrajectory
// (docs/arm.md §7): time_from_start is a builtin_interfaces/Duration {sec, nanosec}.
#include <cmath>
#include <string>

#include "clearshape/arm/trajectory.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"

namespace clearshape::arm {

namespace {

constexpr char kSuffix[] = "_rad";

nlohmann::ordered_json duration_json(double t_s) {
  auto sec = static_cast<long long>(std::floor(t_s));
  auto nanosec = std::llround((t_s - static_cast<double>(sec)) * 1e9);
  if (nanosec >= 1000000000LL) {
    ++sec;
    nanosec -= 1000000000LL;
  }
  return {{"sec", sec}, {"nanosec", nanosec}};
}

std::vector<double> row(const Eigen::MatrixXd& m, std::size_t k) {
  const Eigen::VectorXd r = m.row(static_cast<Eigen::Index>(k));
  return {r.data(), r.data() + r.size()};
}

const nlohmann::json& field(const nlohmann::json& parent, const char* key, const std::string& source,
                            const std::string& where) {
  if (!parent.is_object() || !parent.contains(key)) {
    throw InputError(source, 0, where + key, "is missing (a ROS JointTrajectory needs it)");
  }
  return parent.at(key);
}

// A JSON array of `n` numbers (or empty, read as zeros, when `optional`).
Eigen::VectorXd numbers(const nlohmann::json& j, std::size_t n, bool optional, const std::string& source,
                        const std::string& where) {
  if (optional && j.is_array() && j.empty()) return Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n));
  if (!j.is_array() || j.size() != n) {
    throw InputError(source, 0, where, "must be an array of " + std::to_string(n) + " numbers (one per joint)");
  }
  Eigen::VectorXd v(static_cast<Eigen::Index>(n));
  for (std::size_t i = 0; i < n; ++i) {
    if (!j[i].is_number() || !std::isfinite(j[i].get<double>())) {
      throw InputError(source, 0, where + "[" + std::to_string(i) + "]", "must be a finite number");
    }
    v(static_cast<Eigen::Index>(i)) = j[i].get<double>();
  }
  return v;
}

double duration_s(const nlohmann::json& d, const std::string& source, const std::string& where) {
  const nlohmann::json& sec = field(d, "sec", source, where + ".");
  const nlohmann::json& ns = field(d, "nanosec", source, where + ".");
  if (!sec.is_number_integer() || sec.get<long long>() < 0 || !ns.is_number_integer() || ns.get<long long>() < 0 ||
      ns.get<long long>() >= 1000000000LL) {
    throw InputError(source, 0, where, "needs integer sec >= 0 and nanosec in [0, 999999999]");
  }
  return static_cast<double>(sec.get<long long>()) + 1e-9 * static_cast<double>(ns.get<long long>());
}

}  // namespace

std::string trajectory_csv(const JointTrajectory& trajectory) {
  trajectory.validate();
  std::vector<std::string> names{"time_s"};
  std::vector<std::vector<double>> columns;
  for (std::size_t i = 0; i < trajectory.joint_names.size(); ++i) {
    names.push_back(trajectory.joint_names[i] + kSuffix);
    const Eigen::VectorXd c = trajectory.position_rad.col(static_cast<Eigen::Index>(i));
    columns.emplace_back(c.data(), c.data() + c.size());
  }
  std::vector<const std::vector<double>*> pointers{&trajectory.time_s};
  for (const auto& c : columns) pointers.push_back(&c);
  return io::format_csv(names, pointers);
}

void write_trajectory_csv(const std::filesystem::path& path, const JointTrajectory& trajectory) {
  io::write_text_atomic(path, trajectory_csv(trajectory));
}

JointTrajectory read_trajectory_csv(const std::filesystem::path& path) {
  const io::Table table = io::read_table(path);
  JointTrajectory t;
  t.time_s = table.column("time_s");
  std::vector<const std::vector<double>*> columns;
  for (const std::string& name : table.names) {
    if (name == "time_s") continue;
    if (name.size() <= 4 || !name.ends_with(kSuffix)) {
      throw InputError(path.string(), 1, name, "is not a joint column; allowed: time_s, <joint>_rad");
    }
    t.joint_names.push_back(name.substr(0, name.size() - 4));
    columns.push_back(&table.column(name));
  }
  const auto rows = static_cast<Eigen::Index>(t.time_s.size()), cols = static_cast<Eigen::Index>(columns.size());
  t.position_rad.resize(rows, cols);
  for (Eigen::Index i = 0; i < cols; ++i) {
    t.position_rad.col(i) = Eigen::Map<const Eigen::VectorXd>(columns[static_cast<std::size_t>(i)]->data(), rows);
  }
  t.velocity_rad_s.setZero(rows, cols);
  t.acceleration_rad_s2.setZero(rows, cols);
  t.validate();
  return t;
}

nlohmann::ordered_json trajectory_json(const JointTrajectory& trajectory) {
  trajectory.validate();
  nlohmann::ordered_json doc = io::make_document();
  doc["header"] = {{"stamp", {{"sec", 0}, {"nanosec", 0}}}, {"frame_id", ""}};
  doc["joint_names"] = trajectory.joint_names;
  nlohmann::ordered_json points = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < trajectory.time_s.size(); ++k) {
    points.push_back({{"positions", row(trajectory.position_rad, k)},
                      {"velocities", row(trajectory.velocity_rad_s, k)},
                      {"accelerations", row(trajectory.acceleration_rad_s2, k)},
                      {"effort", nlohmann::ordered_json::array()},
                      {"time_from_start", duration_json(trajectory.time_s[k])}});
  }
  doc["points"] = std::move(points);
  return doc;
}

void write_trajectory_json(const std::filesystem::path& path, const JointTrajectory& trajectory) {
  io::write_json(path, trajectory_json(trajectory));
}

JointTrajectory trajectory_from_json(const nlohmann::json& document, const std::string& source) {
  const nlohmann::json& names = field(document, "joint_names", source, "");
  JointTrajectory t;
  if (!names.is_array() || names.empty()) throw InputError(source, 0, "joint_names", "must be a non-empty array");
  for (const auto& n : names) {
    if (!n.is_string()) throw InputError(source, 0, "joint_names", "must hold strings");
    t.joint_names.push_back(n.get<std::string>());
  }
  const nlohmann::json& points = field(document, "points", source, "");
  if (!points.is_array() || points.empty()) throw InputError(source, 0, "points", "must be a non-empty array");
  const std::size_t n = t.joint_names.size();
  const auto rows = static_cast<Eigen::Index>(points.size()), cols = static_cast<Eigen::Index>(n);
  t.position_rad.resize(rows, cols);
  t.velocity_rad_s.resize(rows, cols);
  t.acceleration_rad_s2.resize(rows, cols);
  for (std::size_t k = 0; k < points.size(); ++k) {
    const std::string p = "points[" + std::to_string(k) + "].";
    const auto r = static_cast<Eigen::Index>(k);
    t.position_rad.row(r) = numbers(field(points[k], "positions", source, p), n, false, source, p + "positions");
    t.velocity_rad_s.row(r) = numbers(field(points[k], "velocities", source, p), n, true, source, p + "velocities");
    t.acceleration_rad_s2.row(r) =
        numbers(field(points[k], "accelerations", source, p), n, true, source, p + "accelerations");
    t.time_s.push_back(duration_s(field(points[k], "time_from_start", source, p), source, p + "time_from_start"));
    if (k > 0 && !(t.time_s[k] > t.time_s[k - 1])) {
      throw InputError(source, 0, p + "time_from_start", "must be later than the previous point's");
    }
  }
  return t;
}

JointTrajectory read_trajectory_json(const std::filesystem::path& path) {
  const std::string text = io::read_text_file(path);
  nlohmann::json doc;
  try {
    doc = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(path.string(), 0, "", std::string("is not JSON: ") + e.what());
  }
  return trajectory_from_json(doc, path.string());
}

}  // namespace clearshape::arm
