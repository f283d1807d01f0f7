// The clearance-model fit of stage 4 (thesis §4.2, Fig. 4.18–4.20; study/model.hpp).
//
// The fit (fit_clearance): start values from the identified link mode (K/J = ω², D/J = 2ζω of a
// linear flank) and a short scan of the play; NLopt BOBYQA on scaled variables (log K_ref with
// K_ref = K·δ_ref^(n−1) the secant stiffness at a reference deflection, which decorrelates K from
// n; log D; log play; n), a multi-start over a grid of exponents and a final refinement with n
// free; stopped by a trust radius of 1e-3 (parameters to ≈ 0.1 %); local 1σ from σ²(JᵀJ)⁻¹.
#include <algorithm>
#include <array>
#include <cmath>
#include <future>
#include <limits>
#include <memory>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <nlopt.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/encoder_speed.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/plant/gyroscope.hpp"
#include "clearshape/study/measures.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::study {

namespace {

enum Param : std::size_t { kStiffness = 0, kDamping = 1, kPlay = 2, kExponent = 3 };
constexpr std::array<const char*, 4> kParamNames{"stiffness", "damping", "play", "exponent"};

// Fit variables, all four: u = (log K_ref, log D, log play, n).
using Vars = std::array<double, 4>;

struct Setup {
  const ClearanceFitProblem* p = nullptr;
  std::array<bool, 4> free{};
  double delta_ref_rad = 1e-3;
  Vars lower{}, upper{};
  std::size_t samples = 0;
  double low_pass_hz = 0.0;  // the sensor low-pass applied to the model's link rate
  std::array<double, 4> step{0.3, 0.3, 0.3, 0.15};  // initial steps (sensitivity-scaled)
};

ClearanceModel model_of(const Setup& s, const Vars& u) {
  ClearanceModel m = s.p->start;
  m.exponent = u[kExponent];
  m.damping = std::exp(u[kDamping]);
  m.play_rad = std::exp(u[kPlay]);
  // K_ref = K·δ_ref^(n−1): the secant stiffness of Eq. 4.3 at the reference deflection.
  m.stiffness = s.free[kStiffness] ? std::exp(u[kStiffness]) / std::pow(s.delta_ref_rad, m.exponent - 1.0)
                                   : s.p->start.stiffness;
  if (!s.free[kDamping]) m.damping = s.p->start.damping;
  if (!s.free[kPlay]) m.play_rad = s.p->start.play_rad;
  return m;
}

// Residual model − measured over the compared samples (throws RuntimeError if CVODE fails).
std::vector<double> residual(const Setup& s, const ClearanceModel& m) {
  const auto rate = sensed_link_rate_deg_s(*s.p, simulate_drive_command(m, s.p->drive_command, s.p->duration_s), s.low_pass_hz);
  std::vector<double> r(s.samples, 0.0);
  const std::size_t n = std::min(rate.size(), s.samples);
  for (std::size_t k = 0; k < n; ++k) r[k] = rate[k] - s.p->measured_link_rate_deg_s[k];
  for (std::size_t k = n; k < s.samples; ++k) r[k] = -s.p->measured_link_rate_deg_s[k];
  return r;
}

double rms(const std::vector<double>& r) {
  double ss = 0.0;
  for (double e : r) ss += e * e;
  return std::sqrt(ss / static_cast<double>(r.size()));
}

// RMS error of model m; with low_pass_hz < 0, the least over the sensor bandwidth grid (a profile
// over that discrete nuisance: one simulation serves every bandwidth).
double rms_error(const Setup& s, const ClearanceModel& m) {
  if (s.low_pass_hz >= 0.0) return rms(residual(s, m));
  const auto response = simulate_drive_command(m, s.p->drive_command, s.p->duration_s);
  double best = std::numeric_limits<double>::infinity();
  for (double hz : s.p->sensor_low_pass_grid_hz) {
    const std::vector<double> rate = sensed_link_rate_deg_s(*s.p, response, hz);
    double ss = 0.0;
    for (std::size_t k = 0; k < s.samples; ++k) {
      const double e = (k < rate.size() ? rate[k] : 0.0) - s.p->measured_link_rate_deg_s[k];
      ss += e * e;
    }
    best = std::min(best, std::sqrt(ss / static_cast<double>(s.samples)));
  }
  return best;
}

// One BOBYQA search over the variables `active` (the others held at `u`).
struct Search {
  const Setup* s = nullptr;
  std::vector<std::size_t> active;
  Vars u{};
  int evaluations = 0;
  int failures = 0;
  double best = std::numeric_limits<double>::infinity();
  Vars best_u{};
  double fail_value = 1e6;  // an integration failure ranks far above any fitted error
};

double search_objective(unsigned n, const double* x, double* grad, void* data) {
  (void)grad;  // derivative-free
  auto* q = static_cast<Search*>(data);
  Vars u = q->u;
  for (unsigned i = 0; i < n; ++i) u[q->active[i]] = x[i];
  ++q->evaluations;
  double e = q->fail_value;
  try {
    e = rms_error(*q->s, model_of(*q->s, u));
    if (!std::isfinite(e)) e = q->fail_value;
  } catch (const std::exception&) {
    ++q->failures;
  }
  if (e < q->best) {
    q->best = e;
    q->best_u = u;
  }
  // The mean square, not the RMS: near a small residual the RMS is a cone, which BOBYQA's
  // quadratic models fit badly; the mean square is smooth there (same minimiser).
  return e * e;
}

bool is_convergence(nlopt_result r) {
  return r == NLOPT_SUCCESS || r == NLOPT_FTOL_REACHED || r == NLOPT_XTOL_REACHED || r == NLOPT_STOPVAL_REACHED;
}

std::string variable_name(std::size_t i) {
  static constexpr std::array<const char*, 4> v{"log K_ref", "log D", "log play", "n"};
  return fmt::format("{} ({})", kParamNames[i], v[i]);
}

// Initial steps of the search (Setup::step: at most 0.3 in the logs, ±35 %, and 0.15 in n);
// never more than a quarter of the bound interval (BOBYQA needs upper − lower ≥ 2·step).
std::array<double, 4> initial_steps(const Setup& s) {
  std::array<double, 4> step = s.step;
  for (std::size_t i = 0; i < 4; ++i) step[i] = std::min(step[i], 0.25 * (s.upper[i] - s.lower[i]));
  return step;
}

// Validates a search before NLopt sees it: every bound finite and ordered with room for the
// initial step, the start inside its bounds (clamped when it is only rounding off).
void check_search(const Setup& s, Search& q, const std::array<double, 4>& step) {
  for (std::size_t i : q.active) {
    const std::string name = variable_name(i);
    require_finite(name + " lower bound", s.lower[i]);
    require_finite(name + " upper bound", s.upper[i]);
    require_finite(name + " start", q.u[i]);
    if (!(s.upper[i] - s.lower[i] >= 2.0 * step[i]) || !(step[i] > 0.0)) {
      throw_invalid(name + " bound interval", s.upper[i] - s.lower[i],
                    fmt::format(">= 2 × initial step {} (BOBYQA)", step[i]), "widen the parameter's bounds");
    }
    const double slack = 1e-9 * (s.upper[i] - s.lower[i]);
    if (q.u[i] < s.lower[i] - slack || q.u[i] > s.upper[i] + slack) {
      throw_invalid(name + " start", q.u[i], fmt::format("[{}, {}]", s.lower[i], s.upper[i]),
                    "start the fit inside its bounds");
    }
    q.u[i] = std::clamp(q.u[i], s.lower[i], s.upper[i]);
  }
}

struct SearchResult {
  Vars u{};
  double rms = 0.0;
  int evaluations = 0;
  nlopt_result status = NLOPT_FAILURE;
};

SearchResult run_search(const Setup& s, const Vars& start, const std::vector<std::size_t>& active,
                        double tolerance) {
  Search q;
  q.s = &s;
  q.active = active;
  q.u = start;
  q.best_u = start;
  const auto steps = initial_steps(s);
  check_search(s, q, steps);
  if (active.empty()) {
    return {q.u, rms_error(s, model_of(s, q.u)), 1, NLOPT_SUCCESS};
  }
  const auto n = static_cast<unsigned>(active.size());
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(NLOPT_LN_BOBYQA, n), nlopt_destroy);
  if (!opt) throw RuntimeError("clearance fit: NLopt could not create a BOBYQA optimizer (out of memory)");
  std::vector<double> x(n), lo(n), hi(n), step(n), xtol(n);
  for (unsigned i = 0; i < n; ++i) {
    x[i] = q.u[active[i]];
    lo[i] = s.lower[active[i]];
    hi[i] = s.upper[active[i]];
    step[i] = steps[active[i]];
    xtol[i] = tolerance * steps[active[i]] / 0.3;  // the same tolerance after NLopt's rescaling
  }
  const auto check = [&](nlopt_result r, const char* what) {
    if (r < 0) {
      throw RuntimeError(fmt::format("clearance fit: NLopt rejected {}: {} ({})", what, nlopt_result_to_string(r),
                                     nlopt_get_errmsg(opt.get()) ? nlopt_get_errmsg(opt.get()) : "no message"));
    }
  };
  check(nlopt_set_lower_bounds(opt.get(), lo.data()), "the lower bounds");
  check(nlopt_set_upper_bounds(opt.get(), hi.data()), "the upper bounds");
  check(nlopt_set_min_objective(opt.get(), search_objective, &q), "the objective");
  check(nlopt_set_maxeval(opt.get(), s.p->max_evaluations), "max_evaluations");
  check(nlopt_set_xtol_abs(opt.get(), xtol.data()), "the step tolerance");
  check(nlopt_set_ftol_rel(opt.get(), 1e-12), "the function tolerance");
  check(nlopt_set_initial_step(opt.get(), step.data()), "the initial steps");
  double value = 0.0;
  const nlopt_result res = nlopt_optimize(opt.get(), x.data(), &value);
  if (res < 0 && res != NLOPT_ROUNDOFF_LIMITED) {
    const char* msg = nlopt_get_errmsg(opt.get());
    std::string where;
    for (unsigned i = 0; i < n; ++i) {
      where += fmt::format("{}{} in [{}, {}] step {}", i ? "; " : "", variable_name(active[i]), lo[i], hi[i], step[i]);
    }
    throw RuntimeError(fmt::format("clearance fit: NLopt BOBYQA failed: {} ({}); variables: {}",
                                   nlopt_result_to_string(res), msg ? msg : "no message", where));
  }
  if (!std::isfinite(q.best) || q.best >= q.fail_value) {
    throw RuntimeError(fmt::format("clearance fit: every one of {} model simulations failed; check the identified "
                                   "drive and the start values",
                                   q.evaluations));
  }
  return {q.best_u, q.best, q.evaluations, res};
}

// Lag-1 autocorrelation of a residual (for the effective sample count), clipped to [0, 0.999].
double lag1(const std::vector<double>& r) {
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    den += r[k] * r[k];
    if (k > 0) num += r[k] * r[k - 1];
  }
  return den > 0.0 ? std::clamp(num / den, 0.0, 0.999) : 0.0;
}

// Local 1σ of the free variables: σ²(JᵀJ)⁻¹ with σ² = SSR/(N − p), inflated by (1 + ρ)/(1 − ρ)
// for an AR(1) residual of lag-1 correlation ρ (the variance factor of correlated errors).
std::vector<double> std_errors(const Setup& s, const Vars& u, const std::vector<std::size_t>& active) {
  const std::vector<double> r0 = residual(s, model_of(s, u));
  const auto N = static_cast<Eigen::Index>(r0.size());
  const auto p = static_cast<Eigen::Index>(active.size());
  std::vector<double> out(active.size(), std::numeric_limits<double>::quiet_NaN());
  if (p == 0 || N <= p) return out;
  Eigen::MatrixXd J(N, p);
  for (Eigen::Index j = 0; j < p; ++j) {
    const std::size_t i = active[static_cast<std::size_t>(j)];
    const double h = 1e-2;
    Vars a = u, b = u;
    a[i] = std::min(u[i] + h, s.upper[i]);
    b[i] = std::max(u[i] - h, s.lower[i]);
    const auto ra = residual(s, model_of(s, a));
    const auto rb = residual(s, model_of(s, b));
    for (Eigen::Index k = 0; k < N; ++k) {
      J(k, j) = (ra[static_cast<std::size_t>(k)] - rb[static_cast<std::size_t>(k)]) / (a[i] - b[i]);
    }
  }
  const Eigen::MatrixXd JtJ = J.transpose() * J;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(JtJ);
  if (eig.info() != Eigen::Success || !(eig.eigenvalues().minCoeff() > 1e-12 * eig.eigenvalues().maxCoeff())) {
    return out;  // singular: not identifiable together
  }
  double ssr = 0.0;
  for (double e : r0) ssr += e * e;
  const double rho = lag1(r0);
  const double sigma2 = ssr / static_cast<double>(N - p) * (1.0 + rho) / (1.0 - rho);
  const Eigen::MatrixXd cov = sigma2 * JtJ.inverse();
  for (Eigen::Index j = 0; j < p; ++j) out[static_cast<std::size_t>(j)] = std::sqrt(cov(j, j));
  return out;
}

// Contact deflection of a response: |motor − link| − half play, where positive (rad).
double rms_deflection_rad(const ModelResponse& r, double play_rad) {
  double ss = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < r.link_angle_deg.size(); ++k) {
    const double d = std::abs(deg_to_rad(r.motor_angle_deg[k] - r.link_angle_deg[k])) - 0.5 * play_rad;
    if (d > 0.0) {
      ss += d * d;
      ++count;
    }
  }
  return count > 0 ? std::sqrt(ss / static_cast<double>(count)) : 0.0;
}

// The sensor bandwidth of the grid that best explains the record for model m (one simulation).
double choose_low_pass(Setup& s, const ClearanceModel& m, std::vector<std::pair<double, double>>* scan) {
  const auto response = simulate_drive_command(m, s.p->drive_command, s.p->duration_s);
  double best_hz = s.p->sensor_low_pass_grid_hz.front();
  double best = std::numeric_limits<double>::infinity();
  if (scan) scan->clear();
  for (double hz : s.p->sensor_low_pass_grid_hz) {
    const std::vector<double> rate = sensed_link_rate_deg_s(*s.p, response, hz);
    std::vector<double> r(s.samples, 0.0);
    for (std::size_t k = 0; k < s.samples; ++k) {
      r[k] = (k < rate.size() ? rate[k] : 0.0) - s.p->measured_link_rate_deg_s[k];
    }
    const double e = rms(r);
    if (scan) scan->emplace_back(hz, e);
    if (e < best) {
      best = e;
      best_hz = hz;
    }
  }
  return best_hz;
}

}  // namespace

std::vector<double> sensed_link_rate_deg_s(const ClearanceFitProblem& p, const ModelResponse& r,
                                           double low_pass_hz) {
  std::vector<double> rate = r.link_rate_deg_s;
  apply_sensor_low_pass(rate, low_pass_hz, p.drive_command.sample_time_s);
  return rate;
}

std::string clearance_parameter_unit(const std::string& name) {
  if (name == "stiffness") return "N·m/rad^n";
  if (name == "damping" || name == "viscous") return "N·m·s/rad";
  if (name == "play") return "deg";
  if (name == "exponent") return "1";
  if (name == "coulomb") return "N·m";
  return "";
}

void apply_sensor_low_pass(std::vector<double>& rate, double bandwidth_hz, double sample_time_s) {
  if (!(bandwidth_hz > 0.0) || rate.empty()) return;
  require_positive("sample_time_s", sample_time_s);
  // First-order low-pass, y_k = y_{k−1} + a (x_k − y_{k−1}), a = 1 − exp(−2π f_c T_s) (plant/gyroscope.hpp).
  const double a = 1.0 - std::exp(-2.0 * std::acos(-1.0) * bandwidth_hz * sample_time_s);
  double y = rate.front();
  for (double& v : rate) {
    y += a * (v - y);
    v = y;
  }
}

double clearance_agreement(const std::vector<double>& measured, const std::vector<double>& model) {
  const std::size_t n = std::min(measured.size(), model.size());
  if (n == 0) throw InvalidArgument("clearance_agreement: empty signals; allowed: at least one sample");
  double ss = 0.0;
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::size_t k = 0; k < n; ++k) {
    ss += (measured[k] - model[k]) * (measured[k] - model[k]);
    lo = std::min(lo, measured[k]);
    hi = std::max(hi, measured[k]);
  }
  // Eq. 4.1: E = sqrt(Σ (m_j − t_j)² / n) / r, r the range of the reference signal.
  return std::sqrt(ss / static_cast<double>(n)) / (hi - lo);
}

ClearanceFitResult fit_clearance(const ClearanceFitProblem& p) {
  // --- Validate the problem (configuration time: InvalidArgument naming the parameter).
  require_positive("duration_s", p.duration_s);
  require_positive("drive_command.sample_time_s", p.drive_command.sample_time_s);
  require_positive("start.link_inertia_kg_m2", p.start.link_inertia_kg_m2);
  require_in_closed("exponent_min", p.exponent_min, 1.0, 10.0, "Eq. 4.3 needs n >= 1");
  require_in_closed("exponent_max", p.exponent_max, p.exponent_min, 10.0);
  require_positive("step_tolerance", p.step_tolerance);
  if (p.sensor_low_pass_grid_hz.empty()) {
    throw InvalidArgument("clearance fit: sensor_low_pass_grid_hz is empty; allowed: at least one bandwidth (0 = none)");
  }
  for (double hz : p.sensor_low_pass_grid_hz) require_non_negative("sensor_low_pass_grid_hz", hz);
  if (p.max_evaluations < 1) throw_invalid("max_evaluations", p.max_evaluations, ">= 1");
  Setup s;
  s.p = &p;
  s.samples = std::min(sample_count(p.duration_s, p.drive_command.sample_time_s), p.measured_link_rate_deg_s.size());
  if (s.samples < 10) {
    throw_invalid("measured_link_rate_deg_s samples", static_cast<double>(p.measured_link_rate_deg_s.size()),
                  ">= 10 over duration_s", "pass the measured record on the command's grid");
  }
  for (const auto& f : p.free) {
    const auto it = std::find(kParamNames.begin(), kParamNames.end(), f);
    if (it == kParamNames.end()) {
      throw InvalidArgument(fmt::format("clearance fit: '{}' cannot be fitted; allowed: stiffness, damping, play, "
                                        "exponent (the link inertia stays fixed: only K/J and D/J are identifiable)",
                                        f));
    }
    s.free[static_cast<std::size_t>(it - kParamNames.begin())] = true;
  }
  require_positive("start.stiffness", p.start.stiffness);
  require_in_closed("start.exponent", p.start.exponent, 1.0, 10.0);
  if (s.free[kDamping]) require_positive("start.damping", p.start.damping, "a fitted damping starts above 0");
  if (s.free[kPlay]) require_positive("start.play_rad", p.start.play_rad, "a fitted play starts above 0");
  if (p.link_natural_frequency_rad_s != 0.0) {
    require_positive("link_natural_frequency_rad_s", p.link_natural_frequency_rad_s);
    require_non_negative("link_damping_ratio", p.link_damping_ratio);
  }

  // --- Start values. Linear flank from the link mode: K/J = ω², D/J = 2ζω (single-DOF oscillator).
  const double J = p.start.link_inertia_kg_m2;
  const double w = p.link_natural_frequency_rad_s;
  const bool from_mode = w > 0.0;
  double k_lin = from_mode ? J * w * w : p.start.stiffness;
  double d_lin = from_mode && p.link_damping_ratio > 0.0 ? 2.0 * p.link_damping_ratio * w * J : p.start.damping;
  if (!s.free[kDamping]) d_lin = p.start.damping;
  const double play0 = p.start.play_rad;
  std::vector<double> grid;
  if (s.free[kExponent]) {
    for (double n : p.exponent_grid) grid.push_back(std::clamp(n, p.exponent_min, p.exponent_max));
    std::sort(grid.begin(), grid.end());
    grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
    if (grid.empty()) grid.push_back(std::clamp(p.start.exponent, p.exponent_min, p.exponent_max));
  } else {
    grid.push_back(p.start.exponent);
  }
  const double n0 = grid.front();
  // Reference deflection: the RMS contact deflection of the linear-flank start model (or of the
  // protocol's start model without a link mode); it only scales the stiffness variable.
  ClearanceFitResult out;
  int evaluations = 0;
  {
    ClearanceModel lin = p.start;
    if (from_mode) {
      lin.exponent = 1.0;
      lin.stiffness = k_lin;
      lin.damping = d_lin;
    }
    if (!(lin.play_rad > 0.0)) lin.play_rad = 1e-4;
    ++evaluations;
    try {
      const double d = rms_deflection_rad(simulate_drive_command(lin, p.drive_command, p.duration_s), lin.play_rad);
      if (std::isfinite(d) && d > 0.0) s.delta_ref_rad = d;
    } catch (const std::exception&) {
      // keep the 1 mrad default: a scale, not a result
    }
  }
  // Without a link mode the protocol's K is read at its own exponent and carried as K_ref.
  if (!from_mode) k_lin = p.start.stiffness * std::pow(s.delta_ref_rad, p.start.exponent - 1.0);
  Vars u0{std::log(k_lin), std::log(std::max(d_lin, 1e-300)), std::log(std::max(play0, 1e-300)), n0};

  // Bounds: a factor 1000 either way for K_ref and D, 100 below / 30 above the start for the play.
  s.lower = {u0[kStiffness] - std::log(1e3), u0[kDamping] - std::log(1e3), std::log(std::max(play0, 1e-300) / 100.0),
             p.exponent_min};
  s.upper = {u0[kStiffness] + std::log(1e3), u0[kDamping] + std::log(1e3), std::log(std::max(play0, 1e-300) * 30.0),
             p.exponent_max};
  if (!(p.exponent_max > p.exponent_min)) s.upper[kExponent] = p.exponent_min + 1.0;  // n is not searched then

  // Sensor bandwidth: profiled (the best of the grid at every evaluation) until the final search.
  s.low_pass_hz = p.sensor_low_pass_grid_hz.size() > 1 ? -1.0 : p.sensor_low_pass_grid_hz.front();

  // Coarse scans (one variable at a time, the best value starts): K_ref over start × 10^{±1}
  // (the link mode may be a different mode than the joint's), then the play over
  // start × 10^{-1.5 … 0.5}.
  const auto scan = [&](std::size_t i, std::initializer_list<double> decades) {
    double best = std::numeric_limits<double>::infinity();
    double best_u = u0[i];
    for (double e : decades) {
      Vars u = u0;
      u[i] = std::clamp(u0[i] + e * std::log(10.0), s.lower[i], s.upper[i]);
      ++evaluations;
      try {
        const double r = rms_error(s, model_of(s, u));
        if (r < best) {
          best = r;
          best_u = u[i];
        }
      } catch (const std::exception&) {
        // an integration failure just ranks last
      }
    }
    u0[i] = best_u;
  };
  if (s.free[kStiffness]) scan(kStiffness, {-1.0, -0.5, 0.0, 0.5, 1.0});
  // K and D at the start exponent and play (a loose search), with the sensor bandwidth re-chosen
  // for them; then the play scan, where the flank is right.
  std::vector<std::size_t> flank;
  for (std::size_t i : {kStiffness, kDamping}) {
    if (s.free[i]) flank.push_back(i);
  }
  if (!flank.empty()) {
    const SearchResult a = run_search(s, u0, flank, 10.0 * p.step_tolerance);
    evaluations += a.evaluations;
    u0 = a.u;
  }
  if (s.free[kPlay]) scan(kPlay, {-2.0, -1.5, -1.0, -0.5, 0.0, 0.5});
  // Scale the variables by their sensitivity: the step of each is inversely proportional to the
  // residual's change per unit of it (finite differences at the start), so that BOBYQA's
  // trust region sees a round problem; the least sensitive variable keeps the largest step.
  {
    // (With a profiled bandwidth the unfiltered residual serves: a scale, not a result.)
    std::array<double, 4> sens{};
    std::vector<double> base;
    ++evaluations;
    try {
      base = residual(s, model_of(s, u0));
    } catch (const std::exception&) {
      base.clear();
    }
    double most = 0.0;
    for (std::size_t i = 0; i < 4 && !base.empty(); ++i) {
      if (!s.free[i]) continue;
      Vars u = u0;
      const double h = 0.01;
      u[i] = u0[i] + h <= s.upper[i] ? u0[i] + h : u0[i] - h;
      ++evaluations;
      try {
        const auto r = residual(s, model_of(s, u));
        double ss = 0.0;
        for (std::size_t k = 0; k < r.size(); ++k) ss += (r[k] - base[k]) * (r[k] - base[k]);
        sens[i] = std::sqrt(ss) / h;
      } catch (const std::exception&) {
        sens[i] = 0.0;
      }
      most = std::max(most, sens[i]);
    }
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < 4; ++i) {
      if (s.free[i] && sens[i] > 0.0) least = std::min(least, sens[i]);
    }
    if (most > 0.0 && std::isfinite(least)) {
      for (std::size_t i = 0; i < 4; ++i) {
        if (s.free[i] && sens[i] > 0.0) s.step[i] = std::clamp(0.3 * least / sens[i], 2e-3, s.step[i]);
      }
    }
  }
  out.reference_deflection_rad = s.delta_ref_rad;
  out.start_model = model_of(s, u0);
  out.start_rms_error_deg_s = rms_error(s, out.start_model);
  ++evaluations;

  // --- Local searches, one per exponent of the grid (in parallel), then n free.
  std::vector<std::size_t> active;
  for (std::size_t i : {kStiffness, kDamping, kPlay}) {
    if (s.free[i]) active.push_back(i);
  }
  std::vector<std::future<SearchResult>> jobs;
  for (double n : grid) {
    Vars u = u0;
    u[kExponent] = n;
    jobs.push_back(std::async(std::launch::async, [&s, u, &active, &p] { return run_search(s, u, active, 10.0 * p.step_tolerance); }));
  }
  std::vector<SearchResult> results;
  for (std::size_t g = 0; g < jobs.size(); ++g) {
    results.push_back(jobs[g].get());
    const auto& r = results.back();
    evaluations += r.evaluations;
    out.starts.push_back({grid[g], false, r.rms, r.evaluations, nlopt_result_to_string(r.status)});
  }
  SearchResult best;
  best.rms = std::numeric_limits<double>::infinity();
  for (const auto& r : results) {
    if (r.rms < best.rms) best = r;
  }
  // Fix the sensor bandwidth at the best grid point; the final search (n free when it is) runs
  // on that smooth objective and decides convergence.
  const bool profiled = s.low_pass_hz < 0.0;
  if (profiled) {
    s.low_pass_hz = choose_low_pass(s, model_of(s, best.u), nullptr);
    ++evaluations;
  }
  std::vector<std::size_t> final_active = active;
  if (s.free[kExponent]) final_active.push_back(kExponent);
  if (profiled || final_active.size() > active.size()) {
    const SearchResult refined = run_search(s, best.u, final_active, p.step_tolerance);
    evaluations += refined.evaluations;
    out.starts.push_back({refined.u[kExponent], s.free[kExponent], refined.rms, refined.evaluations,
                          nlopt_result_to_string(refined.status)});
    best = refined;
  }
  // Basin hops in the play (its error landscape has side minima where impacts fall a period
  // apart): re-scan it about the optimum and search again from a better point, at most twice.
  if (s.free[kPlay]) {
    for (int hop = 0; hop < 2; ++hop) {
      Vars trial = best.u;
      double trial_rms = best.rms;
      for (double e : {-1.0, -0.5, -0.25, 0.25, 0.5}) {
        Vars u = best.u;
        u[kPlay] = std::clamp(best.u[kPlay] + e * std::log(10.0), s.lower[kPlay], s.upper[kPlay]);
        ++evaluations;
        try {
          const double r = rms_error(s, model_of(s, u));
          if (r < trial_rms) {
            trial_rms = r;
            trial = u;
          }
        } catch (const std::exception&) {
          // an integration failure just ranks last
        }
      }
      if (!(trial_rms < best.rms)) break;
      const SearchResult hopped = run_search(s, trial, final_active, p.step_tolerance);
      evaluations += hopped.evaluations;
      out.starts.push_back({hopped.u[kExponent], s.free[kExponent], hopped.rms, hopped.evaluations,
                            nlopt_result_to_string(hopped.status)});
      if (!(hopped.rms < best.rms)) break;
      best = hopped;
    }
  }
  out.sensor_low_pass_hz = s.low_pass_hz;
  choose_low_pass(s, model_of(s, best.u), &out.sensor_low_pass_scan);
  out.model = model_of(s, best.u);
  out.rms_error_deg_s = best.rms;
  out.evaluations = evaluations;
  out.termination = nlopt_result_to_string(best.status);
  out.converged = is_convergence(best.status);
  {
    const auto rate = sensed_link_rate_deg_s(p, simulate_drive_command(out.model, p.drive_command, p.duration_s), s.low_pass_hz);
    const std::vector<double> measured(p.measured_link_rate_deg_s.begin(),
                                       p.measured_link_rate_deg_s.begin() + static_cast<std::ptrdiff_t>(s.samples));
    out.agreement = clearance_agreement(measured, rate);
  }

  // --- Identifiability at the optimum.
  const std::vector<double> se = std_errors(s, best.u, final_active);
  for (std::size_t i = 0; i < 4; ++i) {
    ClearanceParameter q;
    q.name = kParamNames[i];
    const ClearanceModel& m = out.model;
    const ClearanceModel& m0 = out.start_model;
    q.value = i == kStiffness ? m.stiffness : i == kDamping ? m.damping : i == kPlay ? m.play_rad : m.exponent;
    q.start = i == kStiffness ? m0.stiffness : i == kDamping ? m0.damping : i == kPlay ? m0.play_rad : m0.exponent;
    q.free = s.free[i];
    q.std_error = std::numeric_limits<double>::quiet_NaN();
    if (q.free) {
      const double tol = 1e-6 * (s.upper[i] - s.lower[i]);
      // n >= 1 is Eq. 4.3's own domain: n on 1 means the linear law fits best, not a search cut short.
      const bool domain_limit = i == kExponent && s.lower[i] <= 1.0;
      q.at_bound = (best.u[i] <= s.lower[i] + tol && !domain_limit) || best.u[i] >= s.upper[i] - tol;
      const auto it = std::find(final_active.begin(), final_active.end(), i);
      if (it != final_active.end()) q.std_error = se[static_cast<std::size_t>(it - final_active.begin())];
      q.identifiable = std::isfinite(q.std_error) && q.std_error < 0.1;
    }
    out.parameters.push_back(q);
  }
  return out;
}

}  // namespace clearshape::study
