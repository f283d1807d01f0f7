#pragma once
// Internal: the ODE of a clearance joint (drive + link) with its discrete contact mode, as the
// CVODE engine sees it. State layout: [drive x | joint states | W_diss, W_drive]; the last two
// are work integrals (the dissipated energy and the work of the shaft), integrated alongside
// with negligible error weight (CVODE has no quadratures; CVODES is not linked).
#include <cstddef>
#include <string>
#include <vector>

#include "clearshape/plant/command.hpp"
#include "clearshape/plant/drive.hpp"
#include "clearshape/plant/joint.hpp"
#include "clearshape/plant/simulation.hpp"

namespace clearshape::plant::detail {

/// The command seen by the RHS: a held value (zero-order hold, streaming) or a Command with
/// linear interpolation evaluated at t − delay.
struct InputSignal {
  const Command* command = nullptr;
  double delay_s = 0.0;
  double held = 0.0;
  bool use_held = true;
  double value(double t) const noexcept { return use_held ? held : command->value(t - delay_s); }
  double rate(double t) const noexcept { return use_held ? 0.0 : command->rate(t - delay_s); }
};

struct Sample {
  double motor_angle = 0.0, motor_rate = 0.0, link_angle = 0.0, link_rate = 0.0;
  double relative_angle = 0.0, contact_torque = 0.0, penetration = 0.0, normal_force = 0.0;
  double pivot_x = 0.0, pivot_y = 0.0, friction_force = 0.0;
  double kinetic = 0.0, potential = 0.0, contact_energy = 0.0, dissipated = 0.0, drive_work = 0.0;
  ContactMode mode = ContactMode::free;
};

/// Event sink: unbounded (offline) or with a fixed capacity (streaming, allocation-free).
class EventLog {
 public:
  EventLog(std::vector<ContactEvent>* out, bool bounded) : out_(out), bounded_(bounded) {}
  void push(const ContactEvent& e) noexcept;
  long count = 0;

 private:
  std::vector<ContactEvent>* out_;
  bool bounded_;
};

/// Zeno guard: trips when `events` onsets fall within `window_s`.
class ZenoGuard {
 public:
  void configure(int events, double window_s);
  bool onset(double t) noexcept;
  void clear() noexcept { count_ = 0; head_ = 0; }

 private:
  std::vector<double> times_;
  std::size_t head_ = 0;
  std::size_t count_ = 0;
  double window_s_ = 0.0;
};

/// The drive's state at t = 0: the given one (nd finite values, else InvalidArgument) or the
/// rest state under the command u0 (with the initial motor-angle offset).
DriveModel::Vector initial_drive_state(const DriveModel& drive, const InitialState& init, double u0);

class JointSystem {
 public:
  virtual ~JointSystem() = default;
  int size = 0;        ///< total state dimension (including the 2 work integrals)
  int root_count = 0;
  InputSignal input;
  ContactMode mode = ContactMode::free;

  virtual int rhs(double t, const double* y, double* ydot) noexcept = 0;
  virtual int roots(double t, const double* y, double* g) noexcept = 0;
  virtual bool has_jacobian() const noexcept { return false; }
  /// Dense column-major n×n Jacobian into `jac` (all entries written).
  virtual int jacobian(double, const double*, double*) noexcept { return -1; }
  /// Writes y(0); may process an onset at t = 0 (returns false if nothing special).
  virtual void initial_state(const InitialState& init, double u0, double* y, EventLog& log) = 0;
  virtual void tolerances(const SolverOptions& o, double* atol) const = 0;
  /// At a root return at t: updates the mode, may modify y; true if the integrator restarts.
  virtual bool on_roots(double t, double* y, const int* found, EventLog& log) noexcept = 0;
  /// After a command discontinuity at t (input already updated); may modify y.
  virtual void on_input_jump(double, double*) noexcept {}
  /// Safety net at an output time: an onset or separation CVODE could not see (a root function
  /// exactly 0 when the integrator (re)started, e.g. a start on the boundary at rest) is
  /// processed now. Returns true if the integrator must restart.
  virtual bool check_consistency(double t, double* y, EventLog& log) noexcept = 0;
  virtual void sample(double t, const double* y, Sample& s) const noexcept = 0;
  /// One line describing the state (for error messages).
  virtual std::string describe(double t, const double* y) const = 0;
  virtual void reset_discrete() noexcept = 0;
};

}  // namespace clearshape::plant::detail
