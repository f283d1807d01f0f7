// Extra-insensitive shapers (Singhose, Seering & Singer 1994; Singhose et al. 1996/1997):
// EI, two-hump EI and three-hump EI, defined by their residual-vibration curve.
//
// Definitions used here (r = ω/ωn, V from Eq. 2.19 at the design damping, t1 = 0, ΣA = 1):
//   EI  (3 impulses): V(1) = Vtol with dV/dω(1) = 0 (the hump sits at the design frequency),
//                     and V = 0 at two ratios r1 < 1 < r2.
//   EI2 (4 impulses): V(1) = 0 and V = 0 at r1 < 1 < r2; two humps h1 ∈ (r1,1), h2 ∈ (1,r2)
//                     with V(h) = Vtol and dV/dω(h) = 0.
//   EI3 (5 impulses): V(1) = Vtol at a hump (dV/dω = 0), two more humps of height Vtol and
//                     four zeros of V, interleaved.
// "V = 0" means both quadrature sums of Eq. 2.20 vanish. Each set is a square system; at ζ = 0
// its solution is Singhose's exact closed form, for ζ > 0 it is followed by continuation in ζ
// (design_continuation.cpp). Singhose's published damped curve fits approximate these roots
// (e.g. EI at ζ = 0.1, Vtol = 0.05: amplitudes within 3e-4, times within 0.5 % of a period).
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/design.hpp"
#include "design_detail.hpp"

namespace clearshape::shaping {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Layout of the unknowns: [a1 … a(n−1) | t2 … tn (undamped periods) | zero ratios | hump ratios].
struct HumpSystem {
  int impulses = 3;
  bool zero_at_design = false;
  bool hump_at_design = false;
  int free_zeros = 0;
  int free_humps = 0;

  int unknowns() const { return 2 * (impulses - 1) + free_zeros + free_humps; }

  void unpack(const Eigen::VectorXd& x, std::vector<double>& a, std::vector<double>& t) const {
    const int n = impulses;
    a.assign(static_cast<std::size_t>(n), 0.0);
    t.assign(static_cast<std::size_t>(n), 0.0);
    double sum = 0.0;
    for (int i = 0; i + 1 < n; ++i) {
      a[static_cast<std::size_t>(i)] = x(i);
      sum += x(i);
      t[static_cast<std::size_t>(i + 1)] = x(n - 1 + i);
    }
    a[static_cast<std::size_t>(n - 1)] = 1.0 - sum;  // ΣA = 1 (Eq. 2.21)
  }
  double zero(const Eigen::VectorXd& x, int k) const { return x(2 * (impulses - 1) + k); }
  double hump(const Eigen::VectorXd& x, int k) const { return x(2 * (impulses - 1) + free_zeros + k); }

  // Residuals of the defining equations.
  void equations(const Eigen::VectorXd& x, double zeta, double vtol, Eigen::VectorXd& f) const {
    std::vector<double> a;
    std::vector<double> t;
    unpack(x, a, t);
    int row = 0;
    auto zero_at = [&](double r) {
      const std::complex<double> w = detail::residual_phasor(a, t, kTwoPi * r, zeta);
      f(row++) = w.real();
      f(row++) = w.imag();
    };
    auto hump_at = [&](double r) {
      const std::complex<double> w = detail::residual_phasor(a, t, kTwoPi * r, zeta);
      const std::complex<double> dw = detail::residual_phasor_derivative(a, t, kTwoPi * r, zeta);
      f(row++) = std::abs(w) - vtol;
      f(row++) = 2.0 * (std::conj(w) * dw).real();  // d|W|²/dω = 0: a stationary point
    };
    for (int k = 0; k < free_zeros; ++k) zero_at(zero(x, k));
    if (zero_at_design) zero_at(1.0);
    if (hump_at_design) hump_at(1.0);
    for (int k = 0; k < free_humps; ++k) hump_at(hump(x, k));
  }

  // The admissible branch: positive amplitudes, increasing times, ordered positive ratios.
  bool admissible(const Eigen::VectorXd& x) const {
    std::vector<double> a;
    std::vector<double> t;
    unpack(x, a, t);
    for (double v : a) {
      if (!(v > 0.0)) return false;
    }
    for (std::size_t i = 1; i < t.size(); ++i) {
      if (!(t[i] > t[i - 1])) return false;
    }
    for (int k = 0; k < free_zeros; ++k) {
      if (!(zero(x, k) > 0.0) || (k > 0 && !(zero(x, k) > zero(x, k - 1)))) return false;
    }
    for (int k = 0; k < free_humps; ++k) {
      if (!(hump(x, k) > 0.0)) return false;
    }
    return true;
  }
};

// Solves the system at `mode` from the undamped closed form `x0` and builds the shaper.
Shaper solve_ei(const std::string& name, const HumpSystem& system, Eigen::VectorXd x0,
                const Mode& mode, double vtol) {
  const detail::DampedSystem equations = [&system, vtol](const Eigen::VectorXd& x, double zeta,
                                                         Eigen::VectorXd& f) {
    system.equations(x, zeta, vtol, f);
  };
  const detail::Admissible admissible = [&system](const Eigen::VectorXd& x) { return system.admissible(x); };
  const detail::ContinuationResult result =
      detail::continue_in_damping(equations, std::move(x0), mode.damping_ratio, admissible);
  if (!result.converged) {
    throw InvalidArgument(fmt::format(
        "{}: damping_ratio = {} is out of range for vtol = {}; the {} defining equations have a "
        "positive solution only up to damping_ratio ≈ {:.3f} (beyond it two zeros of V merge). "
        "Use a smaller vtol, a zvd/zvdd shaper, or si", name, mode.damping_ratio, vtol, name,
        result.reached_damping));
  }
  std::vector<double> a;
  std::vector<double> t;
  system.unpack(result.x, a, t);
  const double period_s = kTwoPi / mode.natural_frequency_rad_s;  // times are in undamped periods
  std::vector<Impulse> impulses;
  for (std::size_t i = 0; i < a.size(); ++i) impulses.push_back({t[i] * period_s, a[i]});
  return Shaper(name, std::move(impulses), Shaper::Normalize::yes);
}

void validate(const Mode& mode, double vtol, std::string_view name) {
  detail::validate_mode(mode, name);
  detail::validate_vtol(vtol, name);
}

}  // namespace

Shaper design_ei(const Mode& mode, double vtol) {
  validate(mode, vtol, "ei");
  // Undamped closed form (Singhose et al. 1994): [(1+V)/4, (1−V)/2, (1+V)/4] at [0, T/2, T];
  // V(r) = |(1−V)/2 + (1+V)/2·cos πr| vanishes where cos πr = −(1−V)/(1+V).
  const double r1 = std::acos(-(1.0 - vtol) / (1.0 + vtol)) / std::numbers::pi;
  Eigen::VectorXd x0(6);
  x0 << (1.0 + vtol) / 4.0, (1.0 - vtol) / 2.0, 0.5, 1.0, r1, 2.0 - r1;
  const HumpSystem system{3, false, true, 2, 0};
  return solve_ei("ei", system, x0, mode, vtol);
}

Shaper design_ei2(const Mode& mode, double vtol) {
  validate(mode, vtol, "ei2");
  // Undamped closed form (Singhose et al. 1997): [a1, ½−a1, ½−a1, a1] at 0, T/2, T, 3T/2 with
  // a1 = (3X² + 2X + 3V²)/(16X), X = (V²(√(1−V²) + 1))^(1/3). With c = cos(πr/2),
  // V(r) = |c·(8a1c² − 8a1 + 1)|: zeros at c² = (8a1−1)/(8a1), humps at c² = (8a1−1)/(24a1).
  const double X = std::cbrt(vtol * vtol * (std::sqrt(1.0 - vtol * vtol) + 1.0));
  const double a1 = (3.0 * X * X + 2.0 * X + 3.0 * vtol * vtol) / (16.0 * X);
  const double rz = 2.0 / std::numbers::pi * std::acos(std::sqrt((8.0 * a1 - 1.0) / (8.0 * a1)));
  const double rh = 2.0 / std::numbers::pi * std::acos(std::sqrt((8.0 * a1 - 1.0) / (24.0 * a1)));
  Eigen::VectorXd x0(10);
  x0 << a1, 0.5 - a1, 0.5 - a1, 0.5, 1.0, 1.5, rz, 2.0 - rz, rh, 2.0 - rh;
  const HumpSystem system{4, true, false, 2, 2};
  return solve_ei("ei2", system, x0, mode, vtol);
}

Shaper design_ei3(const Mode& mode, double vtol) {
  validate(mode, vtol, "ei3");
  // Undamped closed form (Singhose et al. 1997): a1 = (1 + 3V + 2√(2V(V+1)))/16, a2 = (1−V)/4,
  // a3 = 1 − 2(a1 + a2), symmetric, at 0 … 2T in T/2 steps. With c = cos πr,
  // V(r) = |4a1c² + 2a2c + a3 − 2a1|: zeros at its roots in c, side humps at c = −a2/(4a1).
  const double a1 = (1.0 + 3.0 * vtol + 2.0 * std::sqrt(2.0 * vtol * (vtol + 1.0))) / 16.0;
  const double a2 = (1.0 - vtol) / 4.0;
  const double a3 = 1.0 - 2.0 * (a1 + a2);
  const double disc = std::sqrt(4.0 * a2 * a2 - 16.0 * a1 * (a3 - 2.0 * a1));
  const double c_low = (-2.0 * a2 - disc) / (8.0 * a1);   // nearer −1: zeros nearer r = 1
  const double c_high = (-2.0 * a2 + disc) / (8.0 * a1);
  const double z_outer = std::acos(c_high) / std::numbers::pi;
  const double z_inner = std::acos(c_low) / std::numbers::pi;
  const double rh = std::acos(-a2 / (4.0 * a1)) / std::numbers::pi;
  Eigen::VectorXd x0(14);
  x0 << a1, a2, a3, a2, 0.5, 1.0, 1.5, 2.0, z_outer, z_inner, 2.0 - z_inner, 2.0 - z_outer, rh,
      2.0 - rh;
  const HumpSystem system{5, false, true, 4, 2};
  return solve_ei("ei3", system, x0, mode, vtol);
}

}  // namespace clearshape::shaping
