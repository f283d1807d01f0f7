#include "clearshape/plant/drive.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/lti/process_model.hpp"

namespace clearshape::plant {

namespace {
void check_siso(const lti::StateSpace& ss, int max_order, const char* what) {
  const auto n = ss.a.rows();
  if (ss.a.cols() != n || ss.b.rows() != n || ss.b.cols() != 1 || ss.c.rows() != 1 ||
      ss.c.cols() != n || ss.d.rows() != 1 || ss.d.cols() != 1) {
    throw InvalidArgument(std::string(what) +
                          ": the drive realization must be SISO (A n×n, B n×1, C 1×n, D 1×1)");
  }
  if (n < 1 || n > max_order) {
    throw_invalid(std::string(what) + ".order", static_cast<double>(n),
                  "1…" + std::to_string(max_order),
                  "reduce the model order (process models have at most 4 states)");
  }
  if (!ss.a.allFinite() || !ss.b.allFinite() || !ss.c.allFinite() || !ss.d.allFinite()) {
    throw InvalidArgument(std::string(what) + ": the realization has non-finite entries");
  }
}
void check_unit_delay(double unit, double delay) {
  require_positive("output_unit_rad", unit, "degrees: 0.017453292519943295");
  require_non_negative("delay_s", delay);
}
}  // namespace

DriveModel DriveModel::position_mode(const lti::StateSpace& ss, double unit, double delay) {
  check_siso(ss, kMaxDriveOrder, "position-mode drive");
  check_unit_delay(unit, delay);
  if (ss.d(0, 0) != 0.0) {
    throw_invalid("position-mode drive.D", ss.d(0, 0), "0",
                  "a position-mode TF must be strictly proper: the motor angle cannot jump");
  }
  DriveModel m;
  m.mode_ = DriveMode::position;
  const auto n = ss.a.rows();
  m.a_ = ss.a;
  m.b_ = ss.b.col(0);
  m.c_angle_ = unit * ss.c.row(0).transpose();
  m.c_rate_ = unit * (ss.c * ss.a).row(0).transpose();  // ω = C(Ax + Bu)
  m.d_rate_ = unit * (ss.c * ss.b)(0, 0);
  m.delay_s_ = delay;
  (void)n;
  return m;
}

DriveModel DriveModel::speed_mode(const lti::StateSpace& ss, double unit, double delay) {
  check_siso(ss, kMaxDriveOrder - 1, "speed-mode drive");
  check_unit_delay(unit, delay);
  const auto n = ss.a.rows();
  DriveModel m;
  m.mode_ = DriveMode::speed;
  m.a_ = Matrix::Zero(n + 1, n + 1);
  m.a_.topLeftCorner(n, n) = ss.a;
  m.a_.block(n, 0, 1, n) = unit * ss.c;  // θ̇ = ω = unit·(C x + D u)
  m.b_ = Vector::Zero(n + 1);
  m.b_.head(n) = ss.b.col(0);
  m.b_(n) = unit * ss.d(0, 0);
  m.c_angle_ = Vector::Zero(n + 1);
  m.c_angle_(n) = 1.0;
  m.c_rate_ = Vector::Zero(n + 1);
  m.c_rate_.head(n) = unit * ss.c.row(0).transpose();
  m.d_rate_ = unit * ss.d(0, 0);
  m.delay_s_ = delay;
  return m;
}

DriveModel DriveModel::from_process_model(DriveMode mode, const lti::ProcessModel& model) {
  const lti::StateSpace ss = model.state_space();
  constexpr double kDeg = 0.017453292519943295;
  return mode == DriveMode::position ? position_mode(ss, kDeg, model.delay_s())
                                     : speed_mode(ss, kDeg, model.delay_s());
}

DriveModel DriveModel::thesis_position_mode() {
  return from_process_model(DriveMode::position, lti::thesis_position_mode_model());
}

DriveModel DriveModel::thesis_speed_mode() {
  return from_process_model(DriveMode::speed, lti::thesis_speed_mode_model());
}

DriveModel DriveModel::first_order_position(double time_constant_s, double unit) {
  require_positive("time_constant_s", time_constant_s);
  lti::StateSpace ss;
  ss.a = Eigen::MatrixXd::Constant(1, 1, -1.0 / time_constant_s);  // 1/(τ s + 1)
  ss.b = Eigen::MatrixXd::Constant(1, 1, 1.0 / time_constant_s);
  ss.c = Eigen::MatrixXd::Constant(1, 1, 1.0);
  ss.d = Eigen::MatrixXd::Zero(1, 1);
  return position_mode(ss, unit, 0.0);
}

DriveModel::Realization DriveModel::realization() const {
  return {mode_, a_, b_, c_angle_, c_rate_, d_rate_, delay_s_};
}

DriveModel DriveModel::from_realization(const Realization& r) {
  const auto n = r.a.rows();
  if (n < 1 || n > kMaxDriveOrder) {
    throw_invalid("drive.order", static_cast<double>(n), "1…" + std::to_string(kMaxDriveOrder));
  }
  if (r.a.cols() != n || r.b.size() != n || r.c_angle.size() != n || r.c_rate.size() != n) {
    throw InvalidArgument("drive realization: a must be n×n and b, c_angle, c_rate n long (n = " +
                          std::to_string(n) + ")");
  }
  if (!r.a.allFinite() || !r.b.allFinite() || !r.c_angle.allFinite() || !r.c_rate.allFinite()) {
    throw InvalidArgument("drive realization: non-finite entries");
  }
  require_finite("drive.d_rate", r.d_rate);
  require_finite("drive.delay_s", r.delay_s);
  require_non_negative("drive.delay_s", r.delay_s);
  DriveModel m;
  m.mode_ = r.mode;
  m.a_ = r.a;
  m.b_ = r.b;
  m.c_angle_ = r.c_angle;
  m.c_rate_ = r.c_rate;
  m.d_rate_ = r.d_rate;
  m.delay_s_ = r.delay_s;
  return m;
}

double DriveModel::acceleration_rad_s2(const Eigen::Ref<const Eigen::VectorXd>& x, double u,
                                       double u_rate) const noexcept {
  double ax = 0.0;
  const auto n = a_.rows();
  for (Eigen::Index i = 0; i < n; ++i) {
    double row = b_(i) * u;
    for (Eigen::Index j = 0; j < n; ++j) row += a_(i, j) * x(j);
    ax += c_rate_(i) * row;
  }
  return ax + d_rate_ * u_rate;
}

DriveModel::Vector DriveModel::rest_state(double command, double angle_offset_rad) const {
  require_finite("command", command);
  require_finite("motor_angle_offset_rad", angle_offset_rad);
  const auto n = a_.rows();
  Vector x = Vector::Zero(n);
  if (mode_ == DriveMode::speed) {
    const auto ns = n - 1;
    if (command != 0.0) {
      const Eigen::MatrixXd as = a_.topLeftCorner(ns, ns);
      Eigen::FullPivLU<Eigen::MatrixXd> lu(as);
      if (!lu.isInvertible()) {
        throw_invalid("command", command, "0 for a speed drive with an integrator",
                      "start the run from rest (command 0)");
      }
      const Eigen::VectorXd xs = lu.solve(-b_.head(ns) * command);
      const double speed = c_rate_.head(ns).dot(xs) + d_rate_ * command;
      if (std::abs(speed) > 0.0) {
        throw_invalid("command", command, "0 (a speed-mode drive is at rest only at zero speed)",
                      "start the run with command 0 and step afterwards");
      }
      x.head(ns) = xs;
    }
    x(ns) = angle_offset_rad;
    return x;
  }
  if (command != 0.0) {
    const Eigen::MatrixXd a = a_;
    Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
    if (!lu.isInvertible()) {
      throw_invalid("command", command, "0 for a drive with an integrator",
                    "start the run from rest (command 0)");
    }
    x = lu.solve(Eigen::VectorXd(-b_ * command));
  }
  return x;
}

double DriveModel::dc_gain() const {
  const auto n = mode_ == DriveMode::speed ? a_.rows() - 1 : a_.rows();
  const Eigen::MatrixXd a = a_.topLeftCorner(n, n);
  Eigen::FullPivLU<Eigen::MatrixXd> lu(a);
  if (!lu.isInvertible()) return std::numeric_limits<double>::infinity();
  const Eigen::VectorXd xs = lu.solve(Eigen::VectorXd(-b_.head(n)));
  const Eigen::VectorXd c = mode_ == DriveMode::speed ? Eigen::VectorXd(c_rate_.head(n))
                                                      : Eigen::VectorXd(c_angle_);
  return c.dot(xs) + (mode_ == DriveMode::speed ? d_rate_ : 0.0);
}

}  // namespace clearshape::plant
