// The clearance fit's machinery (clearance_fit_search.hpp): scaled variables, residual, one
// NLopt BOBYQA search, the local 1σ and the sensor bandwidth choice.
#include "clearance_fit_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::study::fit_detail {

std::string param_name(const Setup& s, std::size_t i) {
  return i == kDamping && s.p->start.contact_law == ContactLawChoice::flores ? "restitution" : kParamNames[i];
}

ClearanceModel model_of(const Setup& s, const Vars& u) {
  ClearanceModel m = s.p->start;
  m.exponent = u[kExponent];
  const bool flores = m.contact_law == ContactLawChoice::flores;
  if (flores) {
    m.restitution = s.free[kDamping] ? u[kDamping] : s.p->start.restitution;  // e, linear in [0.05, 1]
  } else {
    m.damping = std::exp(u[kDamping]);
  }
  m.play_rad = std::exp(u[kPlay]);
  // K_ref = K·δ_ref^(n−1): the secant stiffness of Eq. 4.3 at the reference deflection.
  m.stiffness = s.free[kStiffness] ? std::exp(u[kStiffness]) / std::pow(s.delta_ref_rad, m.exponent - 1.0)
                                   : s.p->start.stiffness;
  if (!s.free[kDamping] || flores) m.damping = s.p->start.damping;
  if (!s.free[kPlay]) m.play_rad = s.p->start.play_rad;
  // The joint's friction (Eq. 2.9, regularized), linear in the record's scales.
  m.coulomb_n_m = s.free[kCoulomb] ? s.coulomb_scale_n_m * u[kCoulomb] : s.p->start.coulomb_n_m;
  m.viscous_n_m_s_per_rad = s.free[kViscous] ? s.viscous_scale * u[kViscous] : s.p->start.viscous_n_m_s_per_rad;
  return m;
}

// Residual of a response through the sensor low-pass at `hz`: model − measured over the compared
// samples, then (with an envelope record) √w × (model envelope − measured envelope).
std::vector<double> residual_of(const Setup& s, const ModelResponse& response, double hz) {
  const auto rate = sensed_link_rate_deg_s(*s.p, response, hz);
  std::vector<double> r(s.samples, 0.0);
  const std::size_t n = std::min(rate.size(), s.samples);
  for (std::size_t k = 0; k < n; ++k) r[k] = rate[k] - s.p->measured_link_rate_deg_s[k];
  for (std::size_t k = n; k < s.samples; ++k) r[k] = -s.p->measured_link_rate_deg_s[k];
  const auto& envelope = s.p->measured_link_rate_envelope_deg_s;
  if (!envelope.empty()) {
    const std::vector<double> model = rate_envelope_deg_s(rate, s.p->envelope_window_s, s.p->drive_command.sample_time_s);
    const double w = std::sqrt(s.p->envelope_weight);
    for (std::size_t k = 0; k < s.samples; ++k) r.push_back(w * ((k < model.size() ? model[k] : 0.0) - envelope[k]));
  }
  return r;
}

std::vector<double> residual(const Setup& s, const ClearanceModel& m) {
  return residual_of(s, simulate_drive_command(m, s.p->drive_command, s.p->duration_s), s.low_pass_hz);
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
  for (double hz : s.p->sensor_low_pass_grid_hz) best = std::min(best, rms(residual_of(s, response, hz)));
  return best;
}

namespace {

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

}  // namespace

bool is_convergence(nlopt_result r) {
  return r == NLOPT_SUCCESS || r == NLOPT_FTOL_REACHED || r == NLOPT_XTOL_REACHED || r == NLOPT_STOPVAL_REACHED;
}

namespace {

std::string variable_name(std::size_t i) {
  static constexpr std::array<const char*, kParams> v{"log K_ref", "log D", "log play", "n", "c/(J·a_ref)", "b·T/J"};
  return fmt::format("{} ({})", kParamNames[i], v[i]);
}

// Initial steps of the search (Setup::step: at most 0.3 in the logs, ±35 %, and 0.15 in n);
// never more than a quarter of the bound interval (BOBYQA needs upper − lower ≥ 2·step).
Vars initial_steps(const Setup& s) {
  Vars step = s.step;
  for (std::size_t i = 0; i < kParams; ++i) step[i] = std::min(step[i], 0.25 * (s.upper[i] - s.lower[i]));
  return step;
}

// Validates a search before NLopt sees it: every bound finite and ordered with room for the
// initial step, the start inside its bounds (clamped when it is only rounding off).
void check_search(const Setup& s, Search& q, const Vars& step) {
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

}  // namespace

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

namespace {

// Lag-1 autocorrelation of a residual (for the effective sample count), clipped to [0, 0.999].
double lag1(const std::vector<double>& r) {
  double num = 0.0, den = 0.0;
  for (std::size_t k = 0; k < r.size(); ++k) {
    den += r[k] * r[k];
    if (k > 0) num += r[k] * r[k - 1];
  }
  return den > 0.0 ? std::clamp(num / den, 0.0, 0.999) : 0.0;
}

}  // namespace

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
  const linalg::SymmetricEigenDecomposition eig = linalg::symmetric_eigen(JtJ);  // compiled once, in core
  if (!eig.converged || !(eig.values.minCoeff() > 1e-12 * eig.values.maxCoeff())) {
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
double choose_low_pass(const Setup& s, const ClearanceModel& m, std::vector<std::pair<double, double>>* scan) {
  const auto response = simulate_drive_command(m, s.p->drive_command, s.p->duration_s);
  double best_hz = s.p->sensor_low_pass_grid_hz.front();
  double best = std::numeric_limits<double>::infinity();
  if (scan) scan->clear();
  for (double hz : s.p->sensor_low_pass_grid_hz) {
    const double e = rms(residual_of(s, response, hz));
    if (scan) scan->emplace_back(hz, e);
    if (e < best) {
      best = e;
      best_hz = hz;
    }
  }
  return best_hz;
}

}  // namespace clearshape::study::fit_detail
