#include "clearshape/arm/simulation.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include <fmt/format.h>

#include "arm_system.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::arm {

void ArmSolverOptions::validate() const {
  require_in_open("solver.relative_tolerance", relative_tolerance, 0.0, 1.0);
  require_positive("solver.angle_tolerance_rad", angle_tolerance_rad);
  require_positive("solver.rate_tolerance_rad_s", rate_tolerance_rad_s);
  require_non_negative("solver.max_step_s", max_step_s);
  if (max_steps_per_output < 1) throw_invalid("solver.max_steps_per_output", static_cast<double>(max_steps_per_output), ">= 1");
}

void ArmSimulationOptions::validate(int dof) const {
  require_positive("duration_s", duration_s);
  require_positive("output_rate_hz", output_rate_hz);
  solver.validate();
  for (const auto* v : {&initial.relative_angle_rad, &initial.link_rate_rad_s}) {
    if (v->size() != 0 && v->size() != dof) {
      throw InvalidArgument(fmt::format("initial state has {} values for {} joints; allowed: {} or none", v->size(), dof, dof));
    }
    if (!v->allFinite()) throw InvalidArgument("initial state must hold finite values");
  }
}

namespace {

int rhs_callback(realtype t, N_Vector y, N_Vector yd, void* user) {
  return static_cast<detail::ArmSystem*>(user)->rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(yd));
}

int root_callback(realtype t, N_Vector y, realtype* g, void* user) {
  static_cast<detail::ArmSystem*>(user)->roots(t, N_VGetArrayPointer(y), g);
  return 0;
}

int jac_callback(realtype t, N_Vector y, N_Vector, SUNMatrix jac, void* user, N_Vector, N_Vector, N_Vector) {
  return static_cast<detail::ArmSystem*>(user)->jacobian(t, N_VGetArrayPointer(y), SUNDenseMatrix_Data(jac));
}

void check(int flag, const char* what) {
  if (flag < 0) throw RuntimeError(fmt::format("CVODE setup failed in {} (flag {})", what, flag));
}

void keep_message(int, const char* module, const char* function, char* text, void* user) {
  *static_cast<std::string*>(user) = fmt::format("{} {}: {}", module, function, text);
}

// CVODE with a dense BDF solver and root finding around an ArmSystem (RAII).
class Integrator {
 public:
  Integrator(detail::ArmSystem& system, const ArmSolverOptions& o) {
    if (SUNContext_Create(nullptr, &ctx_) != 0) throw RuntimeError("CVODE: SUNContext_Create failed");
    const auto n = static_cast<sunindextype>(system.size());
    y_ = N_VNew_Serial(n, ctx_);
    atol_ = N_VNew_Serial(n, ctx_);
    ydot_ = N_VNew_Serial(n, ctx_);
    mem_ = CVodeCreate(CV_BDF, ctx_);
    if (!y_ || !atol_ || !ydot_ || !mem_) throw RuntimeError("CVODE: cannot allocate the integrator");
    N_VConst(0.0, y_);
    system.tolerances(o, N_VGetArrayPointer(atol_));
    check(CVodeInit(mem_, rhs_callback, 0.0, y_), "CVodeInit");
    check(CVodeSVtolerances(mem_, o.relative_tolerance, atol_), "CVodeSVtolerances");
    check(CVodeSetUserData(mem_, &system), "CVodeSetUserData");
    check(CVodeSetMaxNumSteps(mem_, o.max_steps_per_output), "CVodeSetMaxNumSteps");
    check(CVodeSetMaxHnilWarns(mem_, -1), "CVodeSetMaxHnilWarns");
    if (o.max_step_s > 0.0) check(CVodeSetMaxStep(mem_, o.max_step_s), "CVodeSetMaxStep");
    matrix_ = SUNDenseMatrix(n, n, ctx_);
    linear_ = SUNLinSol_Dense(y_, matrix_, ctx_);
    if (!matrix_ || !linear_) throw RuntimeError("CVODE: cannot create the dense linear solver");
    check(CVodeSetLinearSolver(mem_, linear_, matrix_), "CVodeSetLinearSolver");
    if (o.analytic_jacobian) check(CVodeSetJacFn(mem_, jac_callback), "CVodeSetJacFn");
    check(CVodeRootInit(mem_, system.root_count(), root_callback), "CVodeRootInit");
    check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn");
    check(CVodeSetErrHandlerFn(mem_, keep_message, &message), "CVodeSetErrHandlerFn");
  }
  ~Integrator() {
    if (mem_) CVodeFree(&mem_);
    if (linear_) SUNLinSolFree(linear_);
    if (matrix_) SUNMatDestroy(matrix_);
    if (atol_) N_VDestroy(atol_);
    if (ydot_) N_VDestroy(ydot_);
    if (y_) N_VDestroy(y_);
    if (ctx_) SUNContext_Free(&ctx_);
  }
  Integrator(const Integrator&) = delete;
  Integrator& operator=(const Integrator&) = delete;

  double* y() noexcept { return N_VGetArrayPointer(y_); }
  void restart(double t, double stop_s) {
    totals(true);
    check(CVodeReInit(mem_, t, y_), "CVodeReInit");
    check(CVodeSetStopTime(mem_, stop_s), "CVodeSetStopTime");
  }
  int advance(double tout, double& t) noexcept { return CVode(mem_, tout, y_, &t, CV_NORMAL); }
  /// ẏ(t) of CVODE's interpolating polynomial (no right-hand side evaluation), or nullptr when no
  /// step has been taken since the last restart (the polynomial is not set up yet).
  const double* derivative(double t) {
    long steps = 0;
    CVodeGetNumSteps(mem_, &steps);
    if (steps == 0 || CVodeGetDky(mem_, t, 1, ydot_) != CV_SUCCESS) return nullptr;
    return N_VGetArrayPointer(ydot_);
  }
  void roots(int* found) { check(CVodeGetRootInfo(mem_, found), "CVodeGetRootInfo"); }
  /// Steps and right-hand sides since the start (CVodeReInit resets CVODE's own counters).
  void totals(bool carry) {
    long steps = 0, rhs = 0, rhs_jac = 0;
    CVodeGetNumSteps(mem_, &steps);
    CVodeGetNumRhsEvals(mem_, &rhs);
    CVodeGetNumLinRhsEvals(mem_, &rhs_jac);
    current_steps = steps;
    current_rhs = rhs + rhs_jac;
    if (carry) {
      carried_steps += steps;
      carried_rhs += rhs + rhs_jac;
      current_steps = current_rhs = 0;
    }
  }
  long carried_steps = 0, carried_rhs = 0, current_steps = 0, current_rhs = 0;
  /// CVODE's last error message (kept for the RuntimeError instead of printed: a grazing touch
  /// that the loop recovers from by a restart is not an error).
  std::string message;

 private:
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr;
  N_Vector atol_ = nullptr;
  N_Vector ydot_ = nullptr;
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver linear_ = nullptr;
  void* mem_ = nullptr;
};

void allocate(ArmTrace& tr, Eigen::Index rows, int dof) {
  for (Eigen::MatrixXd* m : {&tr.motor_angle_rad, &tr.encoder_angle_rad, &tr.output_angle_rad, &tr.link_angle_rad,
                             &tr.link_rate_rad_s, &tr.contact_torque_n_m}) {
    m->setZero(rows, dof);
  }
  for (Eigen::MatrixXd* m : {&tr.tool_position_m, &tr.gyro_rad_s, &tr.accel_m_s2}) m->setZero(rows, 3);
  for (std::vector<double>* v : {&tr.time_s, &tr.kinetic_j, &tr.potential_j, &tr.contact_energy_j}) {
    v->reserve(static_cast<std::size_t>(rows));
  }
}

// The IMU's true readings → white noise N(0, σ²) per axis and sample, then ±range (ArmImu).
void measure(Eigen::MatrixXd& m, double sigma, double range, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  for (Eigen::Index r = 0; r < m.rows(); ++r) {
    for (Eigen::Index c = 0; c < m.cols(); ++c) {
      const double noisy = sigma > 0.0 ? m(r, c) + sigma * normal(rng) : m(r, c);
      m(r, c) = std::clamp(noisy, -range, range);
    }
  }
}

}  // namespace

ArmTrace simulate_arm(const ArmModel& model, std::span<const plant::Command> commands,
                      const ArmSimulationOptions& options) {
  options.validate(model.dof());
  const std::vector<plant::Command> received = received_commands(model, commands);
  detail::ArmSystem system(model, received);
  Integrator cv(system, options.solver);
  ArmTrace trace;
  const auto rows = static_cast<Eigen::Index>(std::floor(options.duration_s * options.output_rate_hz + 1e-9)) + 1;
  allocate(trace, rows, model.dof());
  system.initial_state(options.initial, cv.y(), trace.events);
  const std::vector<double> jumps = system.discontinuities_s();
  auto next_jump = [&](double t) {
    const auto it = std::upper_bound(jumps.begin(), jumps.end(), t);
    return it == jumps.end() ? options.duration_s * 2.0 + 1.0 : *it;
  };
  double t = 0.0;
  double stop = next_jump(t);
  cv.restart(t, stop);
  std::vector<int> found(static_cast<std::size_t>(system.root_count()));
  system.record(t, cv.y(), nullptr, trace, 0);
  bool after_root = false;
  for (Eigen::Index k = 1; k < rows; ++k) {
    const double tout = static_cast<double>(k) / options.output_rate_hz;
    while (t < tout) {
      const double t_before = t;
      int flag = cv.advance(std::min(tout, stop), t);
      if (flag == CV_ILL_INPUT && after_root) {
        // A grazing touch: a root function still exactly 0 just past the root it returned (a link
        // resting on a flank), which CVODE refuses to continue from ("root found at and very near
        // t"). After a restart CVODE treats a root function that is 0 at the start as inactive.
        t = t_before;
        cv.restart(t, stop);
        flag = cv.advance(std::min(tout, stop), t);
      }
      after_root = flag == CV_ROOT_RETURN;
      if (flag < 0) {
        throw RuntimeError(fmt::format("arm '{}': CVODE failed (flag {}: {}) at {}", model.name, flag, cv.message,
                                       system.describe(t, cv.y())));
      }
      bool restart = false;
      if (flag == CV_ROOT_RETURN) {
        cv.roots(found.data());
        restart = system.on_roots(t, cv.y(), found.data(), trace.events);
      }
      if (t >= stop) {  // a command jump: restart the multistep history there
        stop = next_jump(t);
        restart = true;
      }
      if (restart) cv.restart(t, stop);
    }
    if (system.check_consistency(t, cv.y(), trace.events)) cv.restart(t, stop);
    system.record(t, cv.y(), cv.derivative(t), trace, k);
  }
  std::mt19937_64 rng(model.imu.seed);
  measure(trace.gyro_rad_s, model.imu.gyro_noise_rad_s, model.imu.gyro_range_rad_s, rng);
  measure(trace.accel_m_s2, model.imu.accel_noise_m_s2, model.imu.accel_range_m_s2, rng);
  cv.totals(false);
  trace.steps = cv.carried_steps + cv.current_steps;
  trace.rhs_evaluations = cv.carried_rhs + cv.current_rhs;
  return trace;
}

}  // namespace clearshape::arm
