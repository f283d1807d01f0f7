#pragma once
// Internal: what a RigidChain shares between its copies (src/arm/chain.cpp builds it).
#include <string>
#include <vector>

#include <kdl/chain.hpp>

#include "clearshape/arm/chain.hpp"

namespace clearshape::arm {

struct RigidChain::Data {
  KDL::Chain chain;                 ///< one segment per moving joint (fixed links folded in)
  KDL::Frame tip_offset;            ///< the tip link in the last segment's tip frame
  std::vector<ChainJoint> joints;
  std::string robot_name;
  std::string tip_link;
  Eigen::Vector3d gravity{0.0, 0.0, -9.80665};
};

}  // namespace clearshape::arm
