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

double ChainWorkspace::potential_energy_j(const Eigen::VectorXd& q) {
  // V = −Σ m_i gᵀ c_i: the frames are chained segment by segment (F_i = F_{i−1} · pose_i(q_j))
  KDL::Frame frame = KDL::Frame::Identity();
  double v = 0.0;
  Eigen::Index j = 0;
  for (const KDL::Segment& seg : impl_->chain.segments) {  // every segment moves (chain_data.hpp)
    frame = frame * seg.pose(q(j++));
    const KDL::Vector com = frame * seg.getInertia().getCOG();
    v -= seg.getInertia().getMass() * KDL::dot(impl_->gravity, com);
  }
  return v;
}

double ChainWorkspace::kinetic_energy_j(const Eigen::VectorXd& q, const Eigen::VectorXd& qd) {
  impl_->q.data = q;
  impl_->dynamics.JntToMass(impl_->q, impl_->mass);
  return 0.5 * qd.dot(impl_->mass.data * qd);
}

}  // namespace clearshape::arm
