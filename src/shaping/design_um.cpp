// Unity-magnitude ZV shaper (Singhose, Seering & Singer 1990s; Vaughan's UMZV): impulses
// +1, −1, +1 — the shortest shaper that cancels one mode, at the price of reversing the command.
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "design_detail.hpp"

namespace clearshape::shaping {

// Undamped: [1, −1, 1] at [0, T/6, T/3] (exact). For ζ > 0 the times solve Eq. 2.20 with the
// amplitudes fixed at ±1 (two equations, two unknowns t2, t3), followed by continuation in ζ
// from the undamped form; Vaughan's cubic fits in ζ approximate this root.
Shaper design_um_zv(const Mode& mode) {
  detail::validate_mode(mode, "um-zv");
  constexpr double kTwoPi = 2.0 * std::numbers::pi;
  const std::vector<double> amplitudes{1.0, -1.0, 1.0};
  const detail::DampedSystem equations = [&amplitudes](const Eigen::VectorXd& x, double zeta,
                                                       Eigen::VectorXd& f) {
    const std::vector<double> times{0.0, x(0), x(1)};  // undamped periods
    const std::complex<double> w = detail::residual_phasor(amplitudes, times, kTwoPi, zeta);
    f(0) = w.real();
    f(1) = w.imag();
  };
  const detail::Admissible admissible = [](const Eigen::VectorXd& x) {
    return x(0) > 0.0 && x(1) > x(0);
  };
  Eigen::VectorXd x0(2);
  x0 << 1.0 / 6.0, 1.0 / 3.0;
  const detail::ContinuationResult result =
      detail::continue_in_damping(equations, x0, mode.damping_ratio, admissible);
  if (!result.converged) {
    throw InvalidArgument(fmt::format(
        "um-zv: damping_ratio = {} is out of range; the unity-magnitude ZV times were found only "
        "up to damping_ratio ≈ {:.3f}. Use a positive shaper (zv, zvd)", mode.damping_ratio,
        result.reached_damping));
  }
  const double period_s = kTwoPi / mode.natural_frequency_rad_s;
  return Shaper("um-zv",
                {{0.0, 1.0}, {result.x(0) * period_s, -1.0}, {result.x(1) * period_s, 1.0}},
                Shaper::Normalize::yes);
}

}  // namespace clearshape::shaping
