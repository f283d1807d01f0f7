#include "clearshape/shaping/residual.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "design_detail.hpp"

namespace clearshape::shaping {

namespace detail {

// Eq. 2.19 (Magee & Book 1992) with e^{−ζωt_N} moved inside the sum: each term decays by
// e^{−ζω(t_N−tᵢ)} <= 1, so long shapers and high frequencies cannot overflow.
std::complex<double> residual_phasor(std::span<const double> amplitudes,
                                     std::span<const double> times, double omega_rad_s,
                                     double damping_ratio) noexcept {
  const double t_last = times.back();
  const double sigma = damping_ratio * omega_rad_s;
  const double omega_d = omega_rad_s * std::sqrt(1.0 - damping_ratio * damping_ratio);
  double re = 0.0;
  double im = 0.0;
  for (std::size_t i = 0; i < amplitudes.size(); ++i) {
    const double decay = amplitudes[i] * std::exp(-sigma * (t_last - times[i]));
    re += decay * std::cos(omega_d * times[i]);
    im += decay * std::sin(omega_d * times[i]);
  }
  return {re, im};
}

// d/dω of each term above: [−ζ(t_N − tᵢ) + j√(1−ζ²)tᵢ]·term.
std::complex<double> residual_phasor_derivative(std::span<const double> amplitudes,
                                                std::span<const double> times,
                                                double omega_rad_s, double damping_ratio) noexcept {
  const double t_last = times.back();
  const double root = std::sqrt(1.0 - damping_ratio * damping_ratio);
  const double sigma = damping_ratio * omega_rad_s;
  const double omega_d = omega_rad_s * root;
  std::complex<double> sum{0.0, 0.0};
  for (std::size_t i = 0; i < amplitudes.size(); ++i) {
    const std::complex<double> term =
        amplitudes[i] * std::exp(-sigma * (t_last - times[i])) *
        std::complex<double>(std::cos(omega_d * times[i]), std::sin(omega_d * times[i]));
    sum += std::complex<double>(-damping_ratio * (t_last - times[i]), root * times[i]) * term;
  }
  return sum;
}

}  // namespace detail

namespace {

void validate_actual(const Mode& actual) {
  if (!(std::isfinite(actual.natural_frequency_rad_s) && actual.natural_frequency_rad_s >= 0.0)) {
    throw_invalid("residual vibration: natural_frequency_rad_s", actual.natural_frequency_rad_s,
                  "finite and >= 0");
  }
  require_in_half_open("residual vibration: damping_ratio", actual.damping_ratio, 0.0, 1.0,
                       "V(ω, ζ) (Eq. 2.19) describes an oscillatory mode, which needs ζ < 1");
}

struct Evaluator {
  std::vector<double> amplitudes;
  std::vector<double> times;
  double sum = 1.0;
  double design_rad_s = 1.0;
  double damping = 0.0;

  Evaluator(const Shaper& shaper, double design_frequency_rad_s, double damping_ratio)
      : design_rad_s(design_frequency_rad_s), damping(damping_ratio) {
    for (const Impulse& p : shaper.impulses()) {
      amplitudes.push_back(p.amplitude);
      times.push_back(p.time_s);
    }
    sum = std::abs(shaper.amplitude_sum());
  }
  double operator()(double ratio) const {
    return std::abs(detail::residual_phasor(amplitudes, times, ratio * design_rad_s, damping)) / sum;
  }
  // E(r) = Σ|Aᵢ| e^{−ζ r ω (t_N − tᵢ)} / |ΣA| >= V(r) (triangle inequality on Eq. 2.19), and E
  // never increases with r: where E <= vtol, so is V at that ratio and at every larger one.
  double envelope(double ratio) const {
    const double sigma = damping * ratio * design_rad_s;
    double e = 0.0;
    for (std::size_t i = 0; i < amplitudes.size(); ++i) {
      e += std::abs(amplitudes[i]) * std::exp(-sigma * (times.back() - times[i]));
    }
    return e / sum;
  }
};

// Walks from r = 1 in steps of `step` (sign gives the side) until V exceeds `limit` (or the
// ratio leaves (0, r_max]); returns the last crossing of `vtol` before that, refined by bisection.
// The envelope E >= V (Evaluator::envelope) skips the stretch where E <= vtol, which no crossing
// can lie in: upward the band is then open (r_max); downward the walk starts where E meets vtol.
// Without it a long shaper with a small last impulse (damped mode) took ~10⁹ steps.
double band_edge(const Evaluator& v, double vtol, double limit, double step, double r_max) {
  double origin = 1.0;
  if (v.envelope(1.0) <= vtol) {
    if (step > 0.0) return r_max;
    double low = 0.0;  // E(0) = Σ|A|/|ΣA| >= 1 > vtol
    double high = 1.0;
    for (int i = 0; i < 200 && high - low > 1e-15; ++i) {
      const double mid = 0.5 * (low + high);
      if (v.envelope(mid) <= vtol) high = mid; else low = mid;
    }
    origin = high;
  }
  double last_ok = origin;      // last sample with V <= vtol
  bool have_ok = v(origin) <= vtol;
  double after_ok = origin;     // the sample following last_ok
  bool after_set = false;
  for (long k = 1;; ++k) {
    const double r = origin + static_cast<double>(k) * step;
    if (r <= 0.0) break;            // V(0) = 1 > vtol: the lower edge lies before 0
    if (r > r_max) return r_max;    // the band is open above (documented cap)
    if (step > 0.0 && k % 256 == 0 && v.envelope(r) <= vtol) return r_max;
    const double value = v(r);
    if (value <= vtol) {
      last_ok = r;
      have_ok = true;
      after_set = false;
    } else if (!after_set) {
      after_ok = r;
      after_set = true;
    }
    if (value > limit) break;
  }
  if (!have_ok) return 1.0;
  if (!after_set) after_ok = last_ok + step;  // reached r = 0 from a sample <= vtol
  if (after_ok <= 0.0) after_ok = 0.0;
  // Bisection on [last_ok, after_ok]: V(last_ok) <= vtol < V(after_ok).
  double inside = last_ok;
  double outside = after_ok;
  for (int i = 0; i < 200 && std::abs(outside - inside) > 1e-14; ++i) {
    const double mid = 0.5 * (inside + outside);
    if (v(mid) <= vtol) inside = mid; else outside = mid;
  }
  return 0.5 * (inside + outside);
}

}  // namespace

double residual_vibration(const Shaper& shaper, const Mode& actual) {
  validate_actual(actual);
  const Evaluator v(shaper, actual.natural_frequency_rad_s, actual.damping_ratio);
  return v(1.0);
}

std::vector<SensitivityPoint> sensitivity_curve(const Shaper& shaper, const Mode& design,
                                                double ratio_from, double ratio_to,
                                                std::size_t points) {
  return sensitivity_curve(shaper, design, design.damping_ratio, ratio_from, ratio_to, points);
}

std::vector<SensitivityPoint> sensitivity_curve(const Shaper& shaper, const Mode& design,
                                                double actual_damping, double ratio_from,
                                                double ratio_to, std::size_t points) {
  detail::validate_mode(design, "sensitivity");
  require_in_half_open("sensitivity: actual damping_ratio", actual_damping, 0.0, 1.0,
                       "V(ω, ζ) (Eq. 2.19) describes an oscillatory mode, which needs ζ < 1");
  require_non_negative("sensitivity: ratio_from", ratio_from);
  if (!(std::isfinite(ratio_to) && ratio_to > ratio_from)) {
    throw_invalid("sensitivity: ratio_to", ratio_to, fmt::format("finite and > ratio_from = {}", ratio_from));
  }
  if (points < 2) {
    throw_invalid("sensitivity: points", static_cast<double>(points), ">= 2");
  }
  const Evaluator v(shaper, design.natural_frequency_rad_s, actual_damping);
  std::vector<SensitivityPoint> curve(points);
  const double step = (ratio_to - ratio_from) / static_cast<double>(points - 1);
  for (std::size_t i = 0; i < points; ++i) {
    const double r = i + 1 == points ? ratio_to : ratio_from + static_cast<double>(i) * step;
    curve[i] = {r, v(r)};
  }
  return curve;
}

InsensitivityBand insensitivity(const Shaper& shaper, const Mode& design, double vtol,
                                double hump_tolerance) {
  detail::validate_mode(design, "insensitivity");
  detail::validate_vtol(vtol, "insensitivity");
  require_non_negative("insensitivity: hump_tolerance", hump_tolerance,
                       "it is the relative amount by which interior humps may exceed vtol");
  const Evaluator v(shaper, design.natural_frequency_rad_s, design.damping_ratio);
  // V <= vtol is tested with a relative slack of 1e-9, so a shaper designed to touch vtol (EI
  // at its hump, EI2/EI3 humps) keeps its band despite rounding; the edges move by ~1e-10.
  const double inside = vtol * (1.0 + 1e-9);
  const double limit = inside * (1.0 + hump_tolerance);
  if (!(v(1.0) <= limit)) return {1.0, 1.0};
  // V varies on a ratio scale of about 1/(duration in design periods): sample finer for long
  // shapers so no crossing is stepped over.
  const double periods = shaper.duration_s() * design.natural_frequency_rad_s / (2.0 * std::numbers::pi);
  // Beyond 10⁴ periods the step (≤ 1e-7) makes the walk ~10⁸ samples, and near 10⁵³ periods it
  // falls below the spacing of doubles near r = 1 (the walk then never moves).
  constexpr double kMaxPeriods = 1e4;
  if (!(periods <= kMaxPeriods)) {
    throw_invalid("insensitivity: shaper duration in design periods", periods, "<= 10000",
                  "the band of a shaper lasting that many periods of its mode is not resolved");
  }
  const double step = 1e-3 / std::max(1.0, periods);
  constexpr double kRatioMax = 10.0;
  InsensitivityBand band;
  band.ratio_low = band_edge(v, inside, limit, -step, kRatioMax);
  band.ratio_high = band_edge(v, inside, limit, step, kRatioMax);
  return band;
}

}  // namespace clearshape::shaping
