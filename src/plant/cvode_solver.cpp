#include "cvode_solver.hpp"

#include <cvode/cvode.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>

#include <cmath>
#include <limits>
#include <vector>

#include "clearshape/core/error.hpp"

namespace clearshape::plant::detail {

namespace {

constexpr double kNoStop = 1e300;

int rhs_callback(realtype t, N_Vector y, N_Vector ydot, void* user) {
  auto* s = static_cast<CvodeSolver*>(user);
  return s->system().rhs(t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
}

int root_callback(realtype t, N_Vector y, realtype* g, void* user) {
  auto* s = static_cast<CvodeSolver*>(user);
  return s->system().roots(t, N_VGetArrayPointer(y), g);
}

int jac_callback(realtype t, N_Vector y, N_Vector, SUNMatrix jac, void* user, N_Vector,
                 N_Vector, N_Vector) {
  auto* s = static_cast<CvodeSolver*>(user);
  return s->system().jacobian(t, N_VGetArrayPointer(y), SUNDenseMatrix_Data(jac));
}

void error_callback(int code, const char* module, const char* function, char* msg, void* user) {
  if (code == CV_WARNING) return;  // warnings (e.g. t + h = t) are not failures
  auto* s = static_cast<CvodeSolver*>(user);
  s->message_.assign(module ? module : "CVODE");
  s->message_ += ".";
  s->message_ += function ? function : "";
  s->message_ += ": ";
  s->message_ += msg ? msg : "";
}

void check(int flag, const char* what) {
  if (flag < 0) throw RuntimeError(std::string("CVODE setup failed in ") + what + " (flag " +
                                   std::to_string(flag) + ")");
}

}  // namespace

CvodeSolver::CvodeSolver(JointSystem& system, const SolverOptions& o) : system_(system) {
  o.validate();
  const auto n = static_cast<sunindextype>(system.size);
  if (SUNContext_Create(nullptr, &ctx_) != 0) throw RuntimeError("CVODE: SUNContext_Create failed");
  y_ = N_VNew_Serial(n, ctx_);
  atol_ = N_VNew_Serial(n, ctx_);
  dense_ = N_VNew_Serial(n, ctx_);
  if (!y_ || !atol_ || !dense_) throw RuntimeError("CVODE: cannot allocate state vectors");
  // Fused vector kernels: CVODE's prediction and dense output (CVodeGetDky) become one loop
  // each instead of chains of N_VScale/N_VLinearSum; CVODE clones its work vectors from y_.
  check(N_VEnableFusedOps_Serial(y_, SUNTRUE), "N_VEnableFusedOps_Serial");
  N_VConst(0.0, y_);
  system.tolerances(o, N_VGetArrayPointer(atol_));
  mem_ = CVodeCreate(o.integrator == Integrator::bdf ? CV_BDF : CV_ADAMS, ctx_);
  if (!mem_) throw RuntimeError("CVODE: CVodeCreate failed");
  check(CVodeSetErrHandlerFn(mem_, error_callback, this), "CVodeSetErrHandlerFn");
  check(CVodeInit(mem_, rhs_callback, 0.0, y_), "CVodeInit");
  check(CVodeSVtolerances(mem_, o.relative_tolerance, atol_), "CVodeSVtolerances");
  check(CVodeSetUserData(mem_, this), "CVodeSetUserData");
  check(CVodeSetMaxNumSteps(mem_, o.max_steps_per_output), "CVodeSetMaxNumSteps");
  check(CVodeSetMaxHnilWarns(mem_, -1), "CVodeSetMaxHnilWarns");
  if (o.max_step_s > 0.0) check(CVodeSetMaxStep(mem_, o.max_step_s), "CVodeSetMaxStep");
  if (o.integrator == Integrator::bdf) {
    matrix_ = SUNDenseMatrix(n, n, ctx_);
    linear_ = SUNLinSol_Dense(y_, matrix_, ctx_);
    if (!matrix_ || !linear_) throw RuntimeError("CVODE: cannot create the dense linear solver");
    check(CVodeSetLinearSolver(mem_, linear_, matrix_), "CVodeSetLinearSolver");
    if (system.has_jacobian() && o.analytic_jacobian) {
      check(CVodeSetJacFn(mem_, jac_callback), "CVodeSetJacFn");
    }
  } else {
    nonlinear_ = SUNNonlinSol_FixedPoint(y_, 0, ctx_);
    if (!nonlinear_) throw RuntimeError("CVODE: cannot create the fixed-point solver");
    check(CVodeSetNonlinearSolver(mem_, nonlinear_), "CVodeSetNonlinearSolver");
  }
  if (system.root_count > 0) {
    check(CVodeRootInit(mem_, system.root_count, root_callback), "CVodeRootInit");
    check(CVodeSetNoInactiveRootWarn(mem_), "CVodeSetNoInactiveRootWarn");
  }
}

CvodeSolver::~CvodeSolver() {
  if (mem_) CVodeFree(&mem_);
  if (linear_) SUNLinSolFree(linear_);
  if (nonlinear_) SUNNonlinSolFree(nonlinear_);
  if (matrix_) SUNMatDestroy(matrix_);
  if (atol_) N_VDestroy(atol_);
  if (dense_) N_VDestroy(dense_);
  if (y_) N_VDestroy(y_);
  if (ctx_) SUNContext_Free(&ctx_);
}

double* CvodeSolver::state() noexcept { return N_VGetArrayPointer(y_); }
const double* CvodeSolver::state() const noexcept { return N_VGetArrayPointer(y_); }

int CvodeSolver::restart(double t0) noexcept {
  t_ = t0;
  if (initialized_) add_current(carried_);
  const int flag = CVodeReInit(mem_, t0, y_);
  if (flag < 0) return flag;
  initialized_ = true;
  stop_active_ = stop_active_ && stop_s_ > t0;
  // CVODE 6.4 has no CVodeClearStopTime: a stale stop time is pushed out of reach instead
  applied_stop_s_ = std::numeric_limits<double>::quiet_NaN();
  return apply_stop(stop_active_ ? stop_s_ : kNoStop);
}

int CvodeSolver::apply_stop(double tstop) noexcept {
  if (tstop == applied_stop_s_) return 0;
  const int flag = CVodeSetStopTime(mem_, tstop);
  applied_stop_s_ = flag < 0 ? std::numeric_limits<double>::quiet_NaN() : tstop;
  return flag;
}

int CvodeSolver::set_stop_time(double tstop) noexcept {
  stop_s_ = tstop;
  stop_active_ = std::isfinite(tstop) && tstop > t_;
  return apply_stop(stop_active_ ? tstop : kNoStop);
}

int CvodeSolver::call(double tout, double tstop, bool command_stop, int task,
                      double& tret) noexcept {
  int flag = apply_stop(tstop);
  if (flag < 0) return flag;
  realtype reached = t_;
  flag = CVode(mem_, tout, y_, &reached, task);
  tret = reached;
  if (flag >= 0) t_ = reached;
  if (flag == CV_TSTOP_RETURN) {
    applied_stop_s_ = std::numeric_limits<double>::quiet_NaN();  // CVODE dropped it
    if (command_stop) stop_active_ = false;
  }
  return flag;
}

int CvodeSolver::advance(double tout, double& tret) noexcept {
  return call(tout, stop_active_ ? stop_s_ : kNoStop, stop_active_, CV_NORMAL, tret);
}

int CvodeSolver::advance_one_step(double t_end, double& tret) noexcept {
  const bool command_stop = stop_active_ && stop_s_ <= t_end;
  const int flag = call(t_end, command_stop ? stop_s_ : t_end, command_stop, CV_ONE_STEP, tret);
  return flag == CV_TSTOP_RETURN && !command_stop ? CV_SUCCESS : flag;  // t_end: not a command stop
}

const double* CvodeSolver::interpolate(double t) noexcept {
  if (CVodeGetDky(mem_, t, 0, dense_) < 0) return nullptr;
  return N_VGetArrayPointer(dense_);
}

void CvodeSolver::root_info(int* found) noexcept { CVodeGetRootInfo(mem_, found); }

SolverStats CvodeSolver::stats() noexcept {
  SolverStats s = carried_;
  if (initialized_) add_current(s);
  return s;
}

long CvodeSolver::total_steps() noexcept {
  long v = 0;
  if (initialized_) CVodeGetNumSteps(mem_, &v);
  return carried_.steps + v;
}

void CvodeSolver::add_current(SolverStats& s) noexcept {
  long v = 0;
  if (CVodeGetNumSteps(mem_, &v) >= 0) s.steps += v;
  if (CVodeGetNumRhsEvals(mem_, &v) >= 0) s.rhs_evaluations += v;
  if (matrix_ && CVodeGetNumJacEvals(mem_, &v) >= 0) s.jacobian_evaluations += v;
  if (system_.root_count > 0 && CVodeGetNumGEvals(mem_, &v) >= 0) s.root_evaluations += v;
  if (CVodeGetNumErrTestFails(mem_, &v) >= 0) s.error_test_failures += v;
  if (CVodeGetNumNonlinSolvConvFails(mem_, &v) >= 0) s.nonlinear_convergence_failures += v;
}

std::string describe_cvode_failure(int flag) {
  switch (flag) {
    case CV_TOO_MUCH_WORK:
      return "too many steps between two outputs (CV_TOO_MUCH_WORK): the contact is very stiff "
             "or chattering; raise solver.max_steps_per_output, reduce the contact damping D or "
             "stiffness K, or lower solver.zeno_events so persistent contact is detected sooner";
    case CV_TOO_MUCH_ACC:
      return "the tolerances cannot be met (CV_TOO_MUCH_ACC): raise solver.relative_tolerance "
             "or the absolute tolerances";
    case CV_ERR_FAILURE:
      return "the step size collapsed in repeated error-test failures (CV_ERR_FAILURE): use the "
             "bdf integrator, loosen the tolerances, reduce the contact damping D or stiffness K, "
             "or set solver.max_step_s";
    case CV_CONV_FAILURE:
      return "the Newton iteration failed repeatedly (CV_CONV_FAILURE): the contact is too stiff "
             "for the step; use the bdf integrator with the analytic Jacobian, reduce D or K, or "
             "set a smaller solver.max_step_s";
    case CV_RHSFUNC_FAIL:
    case CV_REPTD_RHSFUNC_ERR:
    case CV_UNREC_RHSFUNC_ERR:
    case CV_FIRST_RHSFUNC_ERR:
      return "the state became non-finite (NaN/Inf) (CVODE flag " + std::to_string(flag) +
             "): the simulation diverged; reduce the contact stiffness K or damping D, tighten "
             "the tolerances or set solver.max_step_s";
    case CV_RTFUNC_FAIL:
      return "the contact-event function failed (non-finite state): the simulation diverged";
    case CV_LSETUP_FAIL:
    case CV_LSOLVE_FAIL:
      return "the linear solver failed (singular iteration matrix): reduce the contact "
             "stiffness or damping, or tighten the tolerances";
    default:
      return "CVODE failed with flag " + std::to_string(flag);
  }
}

}  // namespace clearshape::plant::detail
