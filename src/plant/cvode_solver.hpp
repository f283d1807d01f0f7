#pragma once
// Internal RAII wrapper of SUNDIALS CVODE (6.4) around a JointSystem.
#include <string>

#include "clearshape/plant/simulation.hpp"
#include "joint_system.hpp"

#include <sundials/sundials_context.h>
#include <sundials/sundials_linearsolver.h>
#include <sundials/sundials_matrix.h>
#include <sundials/sundials_nonlinearsolver.h>
#include <sundials/sundials_nvector.h>

namespace clearshape::plant::detail {

class CvodeSolver {
 public:
  CvodeSolver(JointSystem& system, const SolverOptions& options);
  ~CvodeSolver();
  CvodeSolver(const CvodeSolver&) = delete;
  CvodeSolver& operator=(const CvodeSolver&) = delete;

  /// (Re)starts at t0 from `state()` (CVodeReInit after the first call).
  int restart(double t0) noexcept;
  /// CVode in normal mode towards tout; returns the CVODE flag, the reached time in tret.
  int advance(double tout, double& tret) noexcept;
  /// One internal step (CV_ONE_STEP), never past t_end nor the command stop time. Reaching
  /// t_end returns CV_SUCCESS; reaching the command stop returns CV_TSTOP_RETURN.
  int advance_one_step(double t_end, double& tret) noexcept;
  /// y(t) from CVODE's dense output of the last step (t within it); null on failure.
  const double* interpolate(double t) noexcept;
  /// A stop time (+inf: none). Re-applied after every restart.
  int set_stop_time(double tstop) noexcept;
  double stop_time() const noexcept { return stop_s_; }
  double* state() noexcept;
  const double* state() const noexcept;
  void root_info(int* found) noexcept;
  /// Counters since construction (CVodeReInit resets CVODE's own; they are carried over).
  SolverStats stats() noexcept;
  long total_steps() noexcept;
  /// Forgets the counters (a new run); the next restart starts counting afresh.
  void reset_stats() noexcept { carried_ = {}; initialized_ = false; }
  const std::string& message() const noexcept { return message_; }
  void clear_message() noexcept { message_.clear(); }
  double current_time() const noexcept { return t_; }
  JointSystem& system() noexcept { return system_; }

  std::string message_;  // written by the error handler

 private:
  JointSystem& system_;
  SUNContext ctx_ = nullptr;
  N_Vector y_ = nullptr;
  N_Vector atol_ = nullptr;
  N_Vector dense_ = nullptr;  // interpolate() output
  SUNMatrix matrix_ = nullptr;
  SUNLinearSolver linear_ = nullptr;
  SUNNonlinearSolver nonlinear_ = nullptr;
  void* mem_ = nullptr;
  bool initialized_ = false;
  double stop_s_ = 0.0;
  bool stop_active_ = false;
  double applied_stop_s_ = 0.0;  // the stop time CVODE currently holds (NaN: none/unknown)
  int apply_stop(double tstop) noexcept;
  int call(double tout, double tstop, bool command_stop, int task, double& tret) noexcept;
  double t_ = 0.0;
  SolverStats carried_{};
  void add_current(SolverStats& s) noexcept;
};

/// A readable name and remedy for a failing CVODE flag.
std::string describe_cvode_failure(int flag);

}  // namespace clearshape::plant::detail
