#include "clearshape/arm/chain.hpp"

#include "chain_data.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <console_bridge/console.h>
#include <fmt/format.h>
#include <urdf_parser/urdf_parser.h>

#include "clearshape/core/error.hpp"

namespace clearshape::arm {


namespace {

// urdfdom reports why it refuses a document through console_bridge only: collect the errors.
class ErrorCollector final : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
    messages += (messages.empty() ? "" : "; ") + text;
  }
  std::string messages;
};

urdf::ModelInterfaceSharedPtr parse(std::string_view xml, const std::string& file) {
  ErrorCollector collector;
  console_bridge::useOutputHandler(&collector);
  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(std::string(xml));
  } catch (const std::exception& e) {  // urdfdom throws on some malformed numbers
    collector.messages = e.what();
  }
  console_bridge::restorePreviousOutputHandler();
  if (!model) {
    throw InputError(file, 0, "robot",
                     "not a valid URDF document: " +
                         (collector.messages.empty() ? std::string("urdfdom refused it") : collector.messages));
  }
  return model;
}

KDL::Frame to_kdl(const urdf::Pose& p) {
  return KDL::Frame(KDL::Rotation::Quaternion(p.rotation.x, p.rotation.y, p.rotation.z, p.rotation.w),
                    KDL::Vector(p.position.x, p.position.y, p.position.z));
}

// URDF gives the inertia tensor about the centre of mass in the inertial frame; KDL wants it
// about the centre of mass in the link frame: I_link = R I_inertial Rᵀ (a change of basis).
KDL::RigidBodyInertia to_kdl(const urdf::Inertial* in) {
  if (in == nullptr) return KDL::RigidBodyInertia::Zero();
  const KDL::Frame origin = to_kdl(in->origin);
  Eigen::Matrix3d i;
  i << in->ixx, in->ixy, in->ixz, in->ixy, in->iyy, in->iyz, in->ixz, in->iyz, in->izz;
  Eigen::Matrix3d r;
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) r(a, b) = origin.M(a, b);
  }
  const Eigen::Matrix3d rotated = r * i * r.transpose();
  const KDL::RotationalInertia about_com(rotated(0, 0), rotated(1, 1), rotated(2, 2), rotated(0, 1),
                                         rotated(0, 2), rotated(1, 2));
  return KDL::RigidBodyInertia(in->mass, origin.p, about_com);
}

std::string_view type_name(int type) {
  switch (type) {
    case urdf::Joint::PRISMATIC: return "prismatic";
    case urdf::Joint::FLOATING: return "floating";
    case urdf::Joint::PLANAR: return "planar";
    default: return "unknown";
  }
}

// The document and its name, for errors that point at an element.
struct Source {
  std::string_view xml;
  const std::string& file;
};

// The 1-based line of <tag … name="name" …> in the document (0 if not found).
std::size_t line_of(const Source& src, std::string_view tag, std::string_view name) {
  const std::string open = "<" + std::string(tag);
  for (std::size_t at = src.xml.find(open); at != std::string_view::npos; at = src.xml.find(open, at + 1)) {
    const std::string_view element = src.xml.substr(at, src.xml.find('>', at) - at);
    for (const char quote : {'"', '\''}) {
      if (element.find("name=" + std::string(1, quote) + std::string(name) + quote) != std::string_view::npos) {
        return 1 + static_cast<std::size_t>(std::count(src.xml.begin(), src.xml.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
      }
    }
  }
  return 0;
}

[[noreturn]] void refuse(const Source& src, std::string_view tag, std::string_view name, const std::string& problem) {
  throw InputError(src.file, line_of(src, tag, name), fmt::format("{} {}", tag, name), problem);
}

// A URDF joint whose frame is `frame` in the previous moving segment's tip frame → a KDL joint
// turning about the axis through that frame's origin. Only revolute, continuous and fixed joints.
KDL::Joint to_kdl_joint(const urdf::Joint& j, const KDL::Frame& frame, const Source& src) {
  if (j.mimic) refuse(src, "joint", j.name, "a mimic joint couples two joints; allowed: independent revolute joints");
  if (j.type == urdf::Joint::FIXED) return KDL::Joint(j.name, KDL::Joint::Fixed);
  if (j.type != urdf::Joint::REVOLUTE && j.type != urdf::Joint::CONTINUOUS) {
    refuse(src, "joint", j.name,
                     fmt::format("type '{}' is not supported: every joint of the arm is a thesis joint "
                                 "(a drive turning a link through play); allowed: revolute, continuous, fixed",
                                 type_name(j.type)));
  }
  const KDL::Vector axis(j.axis.x, j.axis.y, j.axis.z);
  if (!(axis.Norm() > 0.0) || !std::isfinite(axis.Norm())) {
    refuse(src, "joint", j.name, "axis must be a non-zero finite vector");
  }
  return KDL::Joint(j.name, frame.p, frame.M * (axis / axis.Norm()), KDL::Joint::RotAxis);
}

ChainJoint describe_joint(const urdf::Joint& j) {
  ChainJoint c;
  c.name = j.name;
  c.child_link = j.child_link_name;
  if (j.type == urdf::Joint::REVOLUTE && j.limits) {
    c.limited = true;
    c.lower_rad = j.limits->lower;
    c.upper_rad = j.limits->upper;
  }
  return c;
}

// One KDL segment per moving joint. A fixed joint's link is folded into the segment before it
// (its inertia moved into that segment's frame, I = F·I_child), and its frame into the next
// moving joint, so KDL's passes run over the moving joints only; what follows the last moving
// joint becomes the tip offset. Links fixed to the base do not move and carry no dynamics.
void append_segments(const urdf::ModelInterface& model, RigidChain::Data& d, const Source& src) {
  urdf::LinkConstSharedPtr link = model.getRoot();
  KDL::Frame fixed = KDL::Frame::Identity();  // from the last moving segment's tip
  while (!link->child_joints.empty()) {
    if (link->child_joints.size() > 1) {
      refuse(src, "link", link->name,
                       fmt::format("has {} child joints ('{}', '{}', …): a branching tree is not a serial "
                                   "chain; allowed: one child joint per link",
                                   link->child_joints.size(), link->child_joints[0]->name,
                                   link->child_joints[1]->name));
    }
    const urdf::Joint& j = *link->child_joints.front();
    urdf::LinkConstSharedPtr child = model.getLink(j.child_link_name);
    const KDL::Frame frame = fixed * to_kdl(j.parent_to_joint_origin_transform);
    const KDL::Joint kj = to_kdl_joint(j, frame, src);
    const KDL::RigidBodyInertia inertia = to_kdl(child->inertial.get());
    if (kj.getType() == KDL::Joint::Fixed) {
      fixed = frame;
      if (!d.chain.segments.empty()) {
        KDL::Segment& last = d.chain.segments.back();
        last.setInertia(last.getInertia() + fixed * inertia);
      }
    } else {
      d.chain.addSegment(KDL::Segment(child->name, kj, frame, inertia));
      d.joints.push_back(describe_joint(j));
      fixed = KDL::Frame::Identity();
    }
    link = child;
  }
  d.tip_link = link->name;
  d.tip_offset = fixed;
}

// Every moving joint must carry mass after it, else M(q) is singular.
void require_mass(const RigidChain::Data& d, const Source& src) {
  double mass_after = 0.0;
  int joint = static_cast<int>(d.joints.size());
  for (int s = static_cast<int>(d.chain.getNrOfSegments()) - 1; s >= 0; --s) {
    const KDL::Segment& seg = d.chain.getSegment(static_cast<unsigned>(s));
    mass_after += seg.getInertia().getMass();
    --joint;
    if (!(mass_after > 0.0)) {
      refuse(src, "joint", d.joints[static_cast<std::size_t>(joint)].name,
                       "moves no mass (no <inertial> with mass > 0 after it): its inertia matrix "
                       "would be singular; allowed: links with mass > 0 and inertia");
    }
  }
}

}  // namespace

RigidChain RigidChain::from_urdf(std::string_view urdf_xml, const std::string& file) {
  const urdf::ModelInterfaceSharedPtr model = parse(urdf_xml, file);
  auto d = std::make_shared<Data>();
  d->robot_name = model->getName();
  const Source src{urdf_xml, file};
  append_segments(*model, *d, src);
  if (d->joints.empty()) {
    throw InputError(file, 0, "robot", "has no revolute or continuous joint; allowed: a chain of 1 or more");
  }
  require_mass(*d, src);
  return RigidChain(std::move(d));
}

RigidChain RigidChain::from_urdf_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the URDF file");
  std::ostringstream text;
  text << in.rdbuf();
  return from_urdf(text.str(), path);
}

int RigidChain::dof() const noexcept { return static_cast<int>(data_->joints.size()); }
const std::vector<ChainJoint>& RigidChain::joints() const noexcept { return data_->joints; }
const std::string& RigidChain::robot_name() const noexcept { return data_->robot_name; }
const std::string& RigidChain::tip_link() const noexcept { return data_->tip_link; }
const Eigen::Vector3d& RigidChain::gravity_m_s2() const noexcept { return data_->gravity; }
const RigidChain::Data& RigidChain::data() const noexcept { return *data_; }

RigidChain RigidChain::with_gravity(const Eigen::Vector3d& gravity_m_s2) const {
  if (!gravity_m_s2.allFinite()) throw InvalidArgument("arm gravity_m_s2 must hold 3 finite values");
  auto d = std::make_shared<Data>(*data_);
  d->gravity = gravity_m_s2;
  return RigidChain(std::move(d));
}

}  // namespace clearshape::arm
