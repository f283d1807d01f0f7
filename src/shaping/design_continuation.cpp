// Natural continuation in the damping ratio for the shapers defined by nonlinear equations
// (EI family, UM-ZV): start from the exact undamped closed form and follow the root.
#include <algorithm>
#include <cmath>

#include <unsupported/Eigen/NonLinearOptimization>

#include "design_detail.hpp"

namespace clearshape::shaping::detail {

namespace {

struct Functor {
  const DampedSystem* system;
  double damping;
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    (*system)(x, damping, f);
    return 0;
  }
};

bool solve_at(const DampedSystem& system, Eigen::VectorXd& x, double damping, const Admissible& admissible) {
  Functor functor{&system, damping};
  Eigen::HybridNonLinearSolver<Functor> solver(functor);
  solver.parameters.xtol = 1e-15;
  solver.parameters.maxfev = 400 * (x.size() + 1);
  Eigen::VectorXd trial = x;
  solver.solveNumericalDiff(trial);  // success is judged by the residual below, not the status
  Eigen::VectorXd f(x.size());
  system(trial, damping, f);
  if (!trial.allFinite() || !f.allFinite() || f.cwiseAbs().maxCoeff() > 1e-11) return false;
  if (!admissible(trial)) return false;
  x = trial;
  return true;
}

}  // namespace

ContinuationResult continue_in_damping(const DampedSystem& system, Eigen::VectorXd x0, double target,
                                       const Admissible& admissible) {
  constexpr double kMaxStep = 0.01;
  constexpr double kMinStep = 1e-5;
  ContinuationResult result;
  result.x = std::move(x0);
  double zeta = 0.0;
  double step = kMaxStep;
  while (zeta < target) {
    const double next = std::min(target, zeta + step);
    Eigen::VectorXd x = result.x;
    if (solve_at(system, x, next, admissible)) {
      result.x = x;
      zeta = next;
      step = std::min(kMaxStep, 2.0 * step);
    } else {
      step *= 0.5;
      if (step < kMinStep) {
        result.reached_damping = zeta;
        return result;
      }
    }
  }
  result.reached_damping = target;
  result.converged = true;
  return result;
}

}  // namespace clearshape::shaping::detail
