#include "clearshape/arm/shaper_export.hpp"

#include <functional>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/export/c_header.hpp"
#include "clearshape/io/atomic_file.hpp"

namespace clearshape::arm {

namespace {

std::string c_name_of(const std::string& prefix, const std::string& joint) {
  std::string name = prefix + "_" + joint;
  for (char& c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
    if (!ok) c = '_';
  }
  return name;
}

// What was designed for joint i, as export/ describes it: the joint's dominant mode, or for
// every_mode the convolution over the pose's modes (two modes named; more as a custom shaper).
exports::ShaperDesign design_of(const shaping::Shaper& shaper, const ArmModes& modes, int joint,
                                const MoveShaping& shaping, const std::string& command) {
  exports::ShaperDesign d{.shaper = shaper,
                          .method = shaping.method,
                          .mode = modes.joint_mode(joint),
                          .second_mode = std::nullopt,
                          .vtol = std::nullopt,
                          .band_hz = std::nullopt,
                          .command = command};
  if (shaping.every_mode) {
    d.mode = shaping::Mode{modes.natural_frequency_rad_s(0), modes.damping_ratio(0)};
    if (modes.natural_frequency_rad_s.size() == 2) {
      d.second_mode = shaping::Mode{modes.natural_frequency_rad_s(1), modes.damping_ratio(1)};
    } else {
      d.method = shaping::Method::custom;
      d.mode.reset();
    }
  }
  if (shaping.method == shaping::Method::ei || shaping.method == shaping::Method::ei2 ||
      shaping.method == shaping::Method::ei3) {
    d.vtol = shaping.vtol;
  }
  return d;
}

// One header per joint, joint i's design from `design_of_joint(i)`.
std::vector<JointShaperFile> joint_headers_from(const ArmModel& arm, double sample_time_s, const std::string& prefix,
                                                const std::function<exports::ShaperDesign(int)>& design_of_joint) {
  exports::ExportOptions options;
  options.sample_time_s = sample_time_s;
  std::vector<JointShaperFile> out;
  for (int i = 0; i < arm.dof(); ++i) {
    const std::string& joint = arm.joints[static_cast<std::size_t>(i)].name;
    options.c_name = c_name_of(prefix, joint);
    out.push_back({joint, options.c_name + ".h", options.c_name, exports::to_c_header(design_of_joint(i), options).text});
  }
  return out;
}

}  // namespace

std::vector<JointShaperFile> joint_shaper_headers(const ArmModel& arm, const Eigen::VectorXd& end_pose_rad,
                                                  const MoveShaping& shaping, double sample_time_s,
                                                  const std::string& prefix) {
  if (shaping.schedule == ShaperSchedule::none) {
    throw InvalidArgument("joint_shaper_headers: schedule = unshaped has no shaper to export; allowed: fixed, scheduled");
  }
  const Eigen::VectorXd pose = shaping.schedule == ShaperSchedule::fixed ? workspace_centre(arm) : end_pose_rad;
  const ArmModes modes = joint_modes(arm, pose, shaping.modes);
  const std::vector<shaping::Shaper> shapers = joint_shapers(arm, pose, shaping);
  const std::string command = fmt::format("arm::joint_shaper_headers: arm {}, {} shapers ({}{}) at q = ({}) rad", arm.name,
                                          to_string(shaping.schedule), shaping::to_string(shaping.method),
                                          shaping.every_mode ? ", every mode" : "", fmt::join(pose, ", "));
  return joint_headers_from(arm, sample_time_s, prefix, [&](int i) {
    return design_of(shapers[static_cast<std::size_t>(i)], modes, i, shaping, command);
  });
}

std::vector<JointShaperFile> joint_shaper_headers(const ArmModel& arm, std::span<const shaping::Shaper> shapers,
                                                  double sample_time_s, const std::string& prefix,
                                                  const std::string& command) {
  if (shapers.size() != static_cast<std::size_t>(arm.dof())) {
    throw_invalid("joint_shaper_headers: shapers", static_cast<double>(shapers.size()),
                  fmt::format("{} (one per joint)", arm.dof()));
  }
  return joint_headers_from(arm, sample_time_s, prefix, [&](int i) {
    return exports::ShaperDesign{.shaper = shapers[static_cast<std::size_t>(i)],
                                 .method = shaping::Method::custom,
                                 .mode = std::nullopt,
                                 .second_mode = std::nullopt,
                                 .vtol = std::nullopt,
                                 .band_hz = std::nullopt,
                                 .command = command};
  });
}

void write_joint_shaper_headers(const std::filesystem::path& folder, std::span<const JointShaperFile> files) {
  io::AtomicBatch batch;
  for (const JointShaperFile& f : files) batch.add(folder / f.file_name, f.text);
  batch.commit();
}

}  // namespace clearshape::arm
