#pragma once
// The C-header export per axis (issue 24 item 4; docs/arm.md §7): the shaper joint_shapers()
// designs for each joint, written as one self-contained C99 header per joint by
// export/c_header.hpp (taps as double, float, Q15 and Q31 and an allocation-free streaming
// shaper per type), identifiers prefixed "<prefix>_<joint>". A fixed schedule gives the headers a
// controller keeps; an end-pose schedule gives those of one move.
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/arm/trajectory.hpp"

namespace clearshape::arm {

struct JointShaperFile {
  std::string joint;      ///< the URDF joint's name
  std::string file_name;  ///< "<c_name>.h"
  std::string c_name;     ///< "<prefix>_<joint>", characters other than [A-Za-z0-9_] as '_'
  std::string text;       ///< the header
};

/// One header per joint for the shapers of joint_shapers(arm, end_pose_rad, shaping) on a
/// controller sampling every `sample_time_s`. Throws InvalidArgument for schedule none (nothing
/// to export), a bad sample time, or a prefix that does not start a C identifier.
std::vector<JointShaperFile> joint_shaper_headers(const ArmModel& arm, const Eigen::VectorXd& end_pose_rad,
                                                  const MoveShaping& shaping, double sample_time_s,
                                                  const std::string& prefix = "cs");

/// One header per joint for given shapers (one per joint, e.g. the clearance-aware design of
/// arm/clearance_aware.hpp on every joint), exported as custom shapers without a design mode;
/// `command` describes the design in each header's comment. Throws InvalidArgument for a shaper
/// count other than the joints', a bad sample time or prefix.
std::vector<JointShaperFile> joint_shaper_headers(const ArmModel& arm, std::span<const shaping::Shaper> shapers,
                                                  double sample_time_s, const std::string& prefix,
                                                  const std::string& command);

/// Writes the headers into `folder`, all or none (io::AtomicBatch).
void write_joint_shaper_headers(const std::filesystem::path& folder, std::span<const JointShaperFile> files);

}  // namespace clearshape::arm
