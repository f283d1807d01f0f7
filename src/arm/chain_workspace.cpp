#include <kdl/chain.hpp>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/jntarray.hpp>

#include "chain_data.hpp"
#include "clearshape/arm/chain.hpp"

namespace clearshape::arm {

struct ChainWorkspace::Impl {
  explicit Impl(const RigidChain& c)
      : chain(c.data().chain),
        tip_offset(c.data().tip_offset),
        gravity(c.gravity_m_s2().x(), c.gravity_m_s2().y(), c.gravity_m_s2().z()),
        dynamics(chain, gravity),
        inverse(chain, gravity),
        forward(chain),
        q(chain.getNrOfJoints()),
        qd(chain.getNrOfJoints()),
        qdd(chain.getNrOfJoints()),
        tau(chain.getNrOfJoints()),
        mass(chain.getNrOfJoints()),
        wrenches(chain.getNrOfSegments(), KDL::Wrench::Zero()) {}
  // A copy per workspace: KDL's Joint caches its last pose in mutable members (joint.hpp), so a
  // chain shared by simulations on several threads would be a data race.
  KDL::Chain chain;
  KDL::Frame tip_offset;
  KDL::Vector gravity;
  KDL::ChainDynParam dynamics;
  KDL::ChainIdSolver_RNE inverse;
  KDL::ChainFkSolverPos_recursive forward;
  KDL::JntArray q, qd, qdd, tau;
  KDL::JntSpaceInertiaMatrix mass;
  KDL::Wrenches wrenches;
};

ChainWorkspace::ChainWorkspace(const RigidChain& chain)
    : impl_(std::make_unique<Impl>(chain)) {}

ChainWorkspace::~ChainWorkspace() = default;

void ChainWorkspace::mass_matrix(const Eigen::VectorXd& q, Eigen::MatrixXd& m) {
  impl_->q.data = q;
  impl_->dynamics.JntToMass(impl_->q, impl_->mass);
  m = impl_->mass.data;
}

void ChainWorkspace::bias_torque(const Eigen::VectorXd& q, const Eigen::VectorXd& qd, Eigen::VectorXd& tau) {
  impl_->q.data = q;
  impl_->qd.data = qd;
  impl_->qdd.data.setZero();
  impl_->inverse.CartToJnt(impl_->q, impl_->qd, impl_->qdd, impl_->wrenches, impl_->tau);
  tau = impl_->tau.data;
}

void ChainWorkspace::gravity_torque(const Eigen::VectorXd& q, Eigen::VectorXd& tau) {
  impl_->q.data = q;
  impl_->dynamics.JntToGravity(impl_->q, impl_->tau);
  tau = impl_->tau.data;
}

Eigen::Vector3d ChainWorkspace::tip_position_m(const Eigen::VectorXd& q) {
  impl_->q.data = q;
  KDL::Frame tip;
  impl_->forward.JntToCart(impl_->q, tip);
  const KDL::Vector p = tip * impl_->tip_offset.p;
  return {p.x(), p.y(), p.z()};
}

namespace {

Eigen::Isometry3d from_kdl(const KDL::Frame& f) {
  Eigen::Isometry3d out = Eigen::Isometry3d::Identity();
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) out.linear()(a, b) = f.M(a, b);
    out.translation()(a) = f.p(a);
  }
  return out;
}

Eigen::Vector3d from_kdl(const KDL::Vector& v) { return {v.x(), v.y(), v.z()}; }

}  // namespace

Eigen::Isometry3d ChainWorkspace::tip_pose(const Eigen::VectorXd& q) {
  impl_->q.data = q;
  KDL::Frame tip;
  impl_->forward.JntToCart(impl_->q, tip);
  return from_kdl(tip * impl_->tip_offset);
}

ChainWorkspace::Sample ChainWorkspace::sample(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                              const Eigen::VectorXd& qdd, const Eigen::Vector3d& mount_m) {
  // outward pass in each segment's tip frame, as KDL's ChainIdSolver_RNE (Featherstone §5.3):
  // v_i = X_i⁻¹ v_{i−1} + S_i q̇_i, a_i = X_i⁻¹ a_{i−1} + S_i q̈_i + v_i × S_i q̇_i, a_0 = −g
  KDL::Frame frame = KDL::Frame::Identity();
  KDL::Twist v = KDL::Twist::Zero();
  KDL::Twist a(-impl_->gravity, KDL::Vector::Zero());
  Sample out;
  Eigen::Index j = 0;
  for (const KDL::Segment& seg : impl_->chain.segments) {  // every segment moves (chain_data.hpp)
    const KDL::Frame x = seg.pose(q(j));
    // a turn about the axis a through o (both fixed in the parent frame) moves the tip origin
    // at a × (x.p − o): the joint's unit twist S in the tip frame
    const KDL::Joint& joint = seg.getJoint();
    const KDL::Vector axis = joint.JointAxis();
    const KDL::Twist s = x.M.Inverse(KDL::Twist(axis * (x.p - joint.JointOrigin()), axis));
    const KDL::Twist vj = s * qd(j);
    frame = frame * x;
    v = x.Inverse(v) + vj;
    a = x.Inverse(a) + s * qdd(j) + v * vj;
    const KDL::RigidBodyInertia& inertia = seg.getInertia();
    out.kinetic_j += 0.5 * KDL::dot(v, inertia * v);  // ½ vᵀ I v
    out.potential_j -= inertia.getMass() * KDL::dot(impl_->gravity, frame * inertia.getCOG());
    ++j;
  }
  // the mount in the last segment's frame; spatial velocity and acceleration moved to it
  const KDL::Vector p = impl_->tip_offset * KDL::Vector(mount_m.x(), mount_m.y(), mount_m.z());
  const KDL::Twist vp = v.RefPoint(p);
  const KDL::Twist ap = a.RefPoint(p);
  const KDL::Vector specific = ap.vel + vp.rot * vp.vel;  // classical = spatial + ω × v
  const KDL::Rotation& to_tip = impl_->tip_offset.M;     // last segment's frame → tip link's
  out.tip_pose = from_kdl(frame * impl_->tip_offset);
  out.gyro_rad_s = from_kdl(to_tip.Inverse(vp.rot));
  out.accel_m_s2 = from_kdl(to_tip.Inverse(specific));
  return out;
}

}  // namespace clearshape::arm
