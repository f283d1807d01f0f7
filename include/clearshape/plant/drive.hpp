#pragma once
// Drive models: command → motor angle and speed (thesis §3.2, §4.2, Eq. 4.2; docs/design.md §1).
//
// Coupling (docs/design.md §1): the identified transfer functions are the
// closed-loop responses of the servo driver, so the motor motion is *imposed* on the joint
// (one-way coupling): the contact torque of the link does not load the motor. The drive's
// state-space realization is embedded in the ODE state: ẋ = A x + B u(t − T_d).
//   position mode: the TF output is the motor angle in `output_unit_rad` per output unit
//                  (degrees by default) per command unit; the TF must be strictly proper
//                  (the angle cannot jump), and the motor speed is C A x + C B u.
//   speed mode:    the TF output is the motor speed (deg/s per command unit by default);
//                  an integrator state is appended, the motor angle is its integral.
// A process-model delay T_d is applied as a shift of the command in time (exact).
#include <cstdint>

#include <Eigen/Dense>

#include "clearshape/lti/state_space.hpp"

namespace clearshape::lti {
class ProcessModel;
}

namespace clearshape::plant {

enum class DriveMode : std::uint8_t { position, speed };

/// Largest drive state dimension (process models have ≤ 4 states; speed mode adds 1).
inline constexpr int kMaxDriveOrder = 8;

class DriveModel {
 public:
  using Matrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxDriveOrder,
                               kMaxDriveOrder>;
  using Vector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxDriveOrder, 1>;

  /// Angle TF realization (SISO, strictly proper). Throws InvalidArgument on a non-SISO
  /// model, D ≠ 0, non-finite entries, an order above kMaxDriveOrder, or a bad unit/delay.
  static DriveModel position_mode(const lti::StateSpace& angle_per_command,
                                  double output_unit_rad = 0.017453292519943295,
                                  double delay_s = 0.0);
  /// Speed TF realization (SISO, proper); an integrator state gives the angle.
  static DriveModel speed_mode(const lti::StateSpace& speed_per_command,
                               double output_unit_rad = 0.017453292519943295,
                               double delay_s = 0.0);
  /// From an lti::ProcessModel (cascade realization, its delay Td as a command shift); the
  /// model's output is in degrees (position) or deg/s (speed) per command unit.
  static DriveModel from_process_model(DriveMode mode, const lti::ProcessModel& model);
  /// Thesis Eq. 4.2 presets (lti::thesis_position_mode_model / thesis_speed_mode_model).
  static DriveModel thesis_position_mode();
  static DriveModel thesis_speed_mode();
  /// A drive whose angle follows u·output_unit_rad through a first-order lag with time
  /// constant `time_constant_s` (a simple, well-understood drive for tests and examples).
  static DriveModel first_order_position(double time_constant_s,
                                         double output_unit_rad = 0.017453292519943295);

  /// The model's stored realization (the accessors below, together): from_realization() of it
  /// rebuilds the model bit for bit (a copy sent across processes, e.g. a Python pickle).
  struct Realization {
    DriveMode mode = DriveMode::position;
    Matrix a;
    Vector b, c_angle, c_rate;
    double d_rate = 0.0;
    double delay_s = 0.0;
  };
  Realization realization() const;
  /// Throws InvalidArgument naming the field: an order outside 1…kMaxDriveOrder, sizes that do
  /// not match a (n×n), non-finite entries, a negative or non-finite delay.
  static DriveModel from_realization(const Realization& r);

  DriveMode mode() const noexcept { return mode_; }
  int order() const noexcept { return static_cast<int>(a_.rows()); }
  double delay_s() const noexcept { return delay_s_; }
  const Matrix& a() const noexcept { return a_; }
  const Vector& b() const noexcept { return b_; }
  const Vector& angle_output() const noexcept { return c_angle_; }  ///< θ_m = c_angleᵀx (rad)
  const Vector& rate_output() const noexcept { return c_rate_; }    ///< ω_m = c_rateᵀx + d_rate·u
  double rate_feedthrough() const noexcept { return d_rate_; }

  double angle_rad(const Eigen::Ref<const Eigen::VectorXd>& x) const noexcept {
    return c_angle_.dot(x);
  }
  double rate_rad_s(const Eigen::Ref<const Eigen::VectorXd>& x, double u) const noexcept {
    return c_rate_.dot(x) + d_rate_ * u;
  }
  /// α_m = c_rate·(A x + B u) + d_rate·u̇.
  double acceleration_rad_s2(const Eigen::Ref<const Eigen::VectorXd>& x, double u,
                             double u_rate) const noexcept;
  /// State at rest for a constant command u (position mode: −A⁻¹B u; speed mode: requires
  /// zero steady speed, i.e. u = 0, else throws InvalidArgument). Angle offset added to the
  /// integrator in speed mode.
  Vector rest_state(double command, double angle_offset_rad = 0.0) const;
  /// Steady-state motor angle per command unit (position) or speed per command unit (speed).
  double dc_gain() const;

 private:
  DriveModel() = default;
  DriveMode mode_ = DriveMode::position;
  Matrix a_;
  Vector b_;
  Vector c_angle_;
  Vector c_rate_;
  double d_rate_ = 0.0;
  double delay_s_ = 0.0;
};

}  // namespace clearshape::plant
