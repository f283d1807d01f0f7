#pragma once
// Internal helpers shared by the shaper design files and residual.cpp (not installed).
#include <complex>
#include <functional>
#include <span>
#include <string_view>

#include <Eigen/Core>

#include "clearshape/shaping/shaper.hpp"

namespace clearshape::shaping::detail {

/// Residual phasor of raw impulses (not normalised):
/// W(ω) = Σ Aᵢ e^{−ζω(t_N − tᵢ)} e^{jω√(1−ζ²)tᵢ}; V = |W| / ΣA (Eq. 2.19 rewritten so that no
/// exponential grows with t). `times` must be non-empty and end with the largest time.
std::complex<double> residual_phasor(std::span<const double> amplitudes,
                                     std::span<const double> times, double omega_rad_s,
                                     double damping_ratio) noexcept;

/// dW/dω of the phasor above (for stationary-point "hump" conditions: d|W|²/dω = 2 Re(W̄ W')).
std::complex<double> residual_phasor_derivative(std::span<const double> amplitudes,
                                                std::span<const double> times,
                                                double omega_rad_s, double damping_ratio) noexcept;

/// Validates a design mode: ωn finite and > 0, ζ in [0, 1). The ζ >= 1 message says that the
/// mode is not oscillatory and points to `clearshape modes`.
void validate_mode(const Mode& mode, std::string_view method);
/// Validates vtol in (0, 1).
void validate_vtol(double vtol, std::string_view method);

/// K = exp(−ζπ/√(1−ζ²)): decay of the mode over half a damped period (Eq. 2.24).
double half_period_decay(double damping_ratio) noexcept;

/// F(x; ζ): writes the residuals of a square system of defining equations into `f`.
using DampedSystem = std::function<void(const Eigen::VectorXd& x, double damping_ratio, Eigen::VectorXd& f)>;
/// Whether a root is on the admissible branch (positive amplitudes, ordered times, …).
using Admissible = std::function<bool(const Eigen::VectorXd& x)>;

struct ContinuationResult {
  bool converged = false;
  Eigen::VectorXd x;            ///< the root at `reached_damping`
  double reached_damping = 0.0; ///< the target on success; else the last ζ solved
};

/// Follows the root of F(x; ζ) = 0 from `x0` (a root at ζ = 0, e.g. a closed form) to ζ =
/// `target` by natural continuation in ζ: steps of at most 0.01, halved on failure down to
/// 1e-5. Each step is solved by Powell's hybrid method (MINPACK hybrd, Eigen's
/// HybridNonLinearSolver with a forward-difference Jacobian) and accepted when max|F| < 1e-11
/// and `admissible` holds. Deterministic.
ContinuationResult continue_in_damping(const DampedSystem& system, Eigen::VectorXd x0, double target,
                                       const Admissible& admissible);

}  // namespace clearshape::shaping::detail
