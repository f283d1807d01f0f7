// The clearance-model fit of stage 4 (thesis §4.2, Fig. 4.18–4.20; study/model.hpp), in three
// steps with named results between them:
//   plan_fit     validate the problem; start values from the identified link mode (K/J = ω²,
//                D/J = 2ζω of a linear flank); bounds; coarse scans of K_ref, the play and the
//                joint's Coulomb friction; a loose K–D search; steps scaled by sensitivity → FitPlan
//   run_fit      NLopt BOBYQA from every exponent of the grid (n held, in parallel), the sensor
//                bandwidth fixed at the best, a final search with n free, basin hops in the
//                play → FitRun
//   tabulate_fit the model, agreement (Eq. 4.1), per-parameter 1σ from σ²(JᵀJ)⁻¹ → result
// The variables and the search are in clearance_fit_search.hpp.
#include <algorithm>
#include <cmath>
#include <future>
#include <initializer_list>
#include <limits>

#include <fmt/format.h>

#include "clearance_fit_search.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/study/measures.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::study {

namespace {

using namespace fit_detail;

// --- Plan ---------------------------------------------------------------------------------

struct FitPlan {
  Setup s;
  std::vector<double> grid;                // exponents of the multi-start (n held)
  Vars u0{};                               // the start of the searches
  std::vector<std::size_t> active;         // searched at every grid exponent
  std::vector<std::size_t> final_active;   // `active` and n when it is free
  ClearanceModel start_model;
  double start_rms = 0.0;
  int evaluations = 0;                     // model simulations so far
};

// Configuration-time checks that need no simulation (InvalidArgument naming the parameter).
void validate_problem(const ClearanceFitProblem& p) {
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
  if (!p.measured_link_rate_envelope_deg_s.empty()) {
    require_positive("envelope_window_s", p.envelope_window_s);
    require_positive("envelope_weight", p.envelope_weight);
    if (p.measured_link_rate_envelope_deg_s.size() < p.measured_link_rate_deg_s.size()) {
      throw_invalid("measured_link_rate_envelope_deg_s samples", static_cast<double>(p.measured_link_rate_envelope_deg_s.size()),
                    fmt::format(">= the record's {}", p.measured_link_rate_deg_s.size()));
    }
  }
}

// The free parameters, the compared samples and the friction variables' scales.
Setup make_setup(const ClearanceFitProblem& p) {
  Setup s;
  s.p = &p;
  s.samples = std::min(sample_count(p.duration_s, p.drive_command.sample_time_s), p.measured_link_rate_deg_s.size());
  if (s.samples < 10) {
    throw_invalid("measured_link_rate_deg_s samples", static_cast<double>(p.measured_link_rate_deg_s.size()),
                  ">= 10 over duration_s", "pass the measured record on the command's grid");
  }
  const bool flores = p.start.contact_law == ContactLawChoice::flores;
  for (const auto& f : p.free) {
    // The Flores law's dissipation parameter is e: "restitution" names it ("damping" too).
    const auto it = std::find(kParamNames.begin(), kParamNames.end(), flores && f == "restitution" ? "damping" : f);
    if (it == kParamNames.end()) {
      throw InvalidArgument(fmt::format("clearance fit: '{}' cannot be fitted; allowed: stiffness, {}, play, "
                                        "exponent, coulomb, viscous (the link inertia stays fixed: only K/J and D/J "
                                        "are identifiable)",
                                        f, flores ? "restitution" : "damping"));
    }
    s.free[static_cast<std::size_t>(it - kParamNames.begin())] = true;
  }
  require_positive("start.stiffness", p.start.stiffness);
  require_in_closed("start.exponent", p.start.exponent, 1.0, 10.0);
  if (flores) {
    require_in_closed("start.restitution", p.start.restitution, 0.05, 1.0, "the Flores law's e in (0, 1]");
  } else if (s.free[kDamping]) {
    require_positive("start.damping", p.start.damping, "a fitted damping starts above 0");
  }
  if (s.free[kPlay]) require_positive("start.play_rad", p.start.play_rad, "a fitted play starts above 0");
  require_non_negative("start.coulomb_n_m", p.start.coulomb_n_m);
  require_non_negative("start.viscous_n_m_s_per_rad", p.start.viscous_n_m_s_per_rad);
  if (p.link_natural_frequency_rad_s != 0.0) {
    require_positive("link_natural_frequency_rad_s", p.link_natural_frequency_rad_s);
    require_non_negative("link_damping_ratio", p.link_damping_ratio);
  }
  // a_ref = peak |ω| / T (rad/s²) and 1/T: the scales of the friction variables.
  double peak_rad_s = 0.0;
  for (std::size_t k = 0; k < s.samples; ++k) peak_rad_s = std::max(peak_rad_s, std::abs(deg_to_rad(p.measured_link_rate_deg_s[k])));
  if ((s.free[kCoulomb] || s.free[kViscous]) && !(peak_rad_s > 0.0)) {
    throw_invalid("measured_link_rate_deg_s peak", 0.0, "> 0 to fit the joint's friction", "the link must move in the record");
  }
  const double J = p.start.link_inertia_kg_m2;
  s.coulomb_scale_n_m = s.free[kCoulomb] ? J * peak_rad_s / p.duration_s : 1.0;
  s.viscous_scale = J / p.duration_s;
  return s;
}

// The exponents of the multi-start (the problem's n alone when n is fixed).
std::vector<double> exponent_grid(const ClearanceFitProblem& p, const Setup& s) {
  std::vector<double> grid;
  if (!s.free[kExponent]) return {p.start.exponent};
  for (double n : p.exponent_grid) grid.push_back(std::clamp(n, p.exponent_min, p.exponent_max));
  std::sort(grid.begin(), grid.end());
  grid.erase(std::unique(grid.begin(), grid.end()), grid.end());
  if (grid.empty()) grid.push_back(std::clamp(p.start.exponent, p.exponent_min, p.exponent_max));
  return grid;
}

// Start variables and bounds. The flank: linear from the link mode (K/J = ω², D/J = 2ζω of a
// single-DOF oscillator) or the problem's K, D; the stiffness carried as K_ref at the reference
// deflection — the RMS contact deflection of that start model (one simulation; it only scales
// the stiffness variable). Bounds: a factor 1000 either way for K_ref and D, 100 below / 30 above
// the start for the play, [0, 10] for the scaled friction (or 3× a larger start).
Vars start_and_bounds(const ClearanceFitProblem& p, Setup& s, double n0, int& evaluations) {
  const double J = p.start.link_inertia_kg_m2;
  const double w = p.link_natural_frequency_rad_s;
  const bool from_mode = w > 0.0;
  double k_lin = from_mode ? J * w * w : p.start.stiffness;
  double d_lin = from_mode && p.link_damping_ratio > 0.0 ? 2.0 * p.link_damping_ratio * w * J : p.start.damping;
  if (!s.free[kDamping]) d_lin = p.start.damping;
  const bool flores = p.start.contact_law == ContactLawChoice::flores;
  // Flores: e of the link mode's half cycle, e = exp(−πζ/√(1−ζ²)) (inverse of plant::kelvin_voigt_damping_ratio).
  const double zeta = p.link_damping_ratio;
  double e0 = from_mode && s.free[kDamping] && zeta > 0.0 && zeta < 1.0
                  ? std::exp(-std::acos(-1.0) * zeta / std::sqrt(1.0 - zeta * zeta))
                  : p.start.restitution;
  e0 = std::clamp(e0, 0.05, 1.0);
  const double play0 = p.start.play_rad;
  {
    ClearanceModel lin = p.start;
    if (from_mode) {
      lin.exponent = 1.0;
      lin.stiffness = k_lin;
      lin.damping = d_lin;
      lin.restitution = e0;
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
  const Vars u0{std::log(k_lin), flores ? e0 : std::log(std::max(d_lin, 1e-300)), std::log(std::max(play0, 1e-300)), n0,
                p.start.coulomb_n_m / s.coulomb_scale_n_m, p.start.viscous_n_m_s_per_rad / s.viscous_scale};
  s.lower = {u0[kStiffness] - std::log(1e3), flores ? 0.05 : u0[kDamping] - std::log(1e3), std::log(std::max(play0, 1e-300) / 100.0),
             p.exponent_min, 0.0, 0.0};
  s.upper = {u0[kStiffness] + std::log(1e3), flores ? 1.0 : u0[kDamping] + std::log(1e3), std::log(std::max(play0, 1e-300) * 30.0),
             p.exponent_max, std::max(10.0, 3.0 * u0[kCoulomb]), std::max(10.0, 3.0 * u0[kViscous])};
  if (!(p.exponent_max > p.exponent_min)) s.upper[kExponent] = p.exponent_min + 1.0;  // n is not searched then
  return u0;
}

// A coarse scan of variable i over `values` (the others at u0): the best becomes its start; an
// integration failure just ranks last.
void scan(const Setup& s, Vars& u0, std::size_t i, const std::vector<double>& values, int& evaluations) {
  double best = std::numeric_limits<double>::infinity();
  double best_u = u0[i];
  for (double v : values) {
    Vars u = u0;
    u[i] = std::clamp(v, s.lower[i], s.upper[i]);
    ++evaluations;
    try {
      const double r = rms_error(s, model_of(s, u));
      if (r < best) {
        best = r;
        best_u = u[i];
      }
    } catch (const std::exception&) {
    }
  }
  u0[i] = best_u;
}

// Log-variable values u0[i] + d·ln 10 for the decades d.
std::vector<double> decades(const Vars& u0, std::size_t i, std::initializer_list<double> ds) {
  std::vector<double> v;
  for (double d : ds) v.push_back(u0[i] + d * std::log(10.0));
  return v;
}

// Scales the variables by their sensitivity: the step of each is inversely proportional to the
// residual's change per unit of it (finite differences at u0), so that BOBYQA's trust region sees
// a round problem; the least sensitive variable keeps the largest step. (With a profiled
// bandwidth the unfiltered residual serves: a scale, not a result.)
void scale_steps(Setup& s, const Vars& u0, int& evaluations) {
  Vars sens{};
  std::vector<double> base;
  ++evaluations;
  try {
    base = residual(s, model_of(s, u0));
  } catch (const std::exception&) {
    base.clear();
  }
  double most = 0.0;
  for (std::size_t i = 0; i < kParams && !base.empty(); ++i) {
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
  for (std::size_t i = 0; i < kParams; ++i) {
    if (s.free[i] && sens[i] > 0.0) least = std::min(least, sens[i]);
  }
  if (most > 0.0 && std::isfinite(least)) {
    for (std::size_t i = 0; i < kParams; ++i) {
      if (s.free[i] && sens[i] > 0.0) s.step[i] = std::clamp(0.3 * least / sens[i], 2e-3, s.step[i]);
    }
  }
}

// The whole plan: start, scans (K_ref over start × 10^{±1} — the link mode may be another mode
// than the joint's; a loose K–D search at the start exponent and play; the play over
// start × 10^{−2 … 0.5}; the Coulomb friction over 0 and a_ref × 10^{−2 … 0}), scaled steps.
FitPlan plan_fit(const ClearanceFitProblem& p) {
  validate_problem(p);
  FitPlan plan;
  plan.s = make_setup(p);
  Setup& s = plan.s;
  plan.grid = exponent_grid(p, s);
  Vars u0 = start_and_bounds(p, s, plan.grid.front(), plan.evaluations);
  // Sensor bandwidth: profiled (the best of the grid at every evaluation) until the final search.
  s.low_pass_hz = p.sensor_low_pass_grid_hz.size() > 1 ? -1.0 : p.sensor_low_pass_grid_hz.front();
  if (s.free[kStiffness]) scan(s, u0, kStiffness, decades(u0, kStiffness, {-1.0, -0.5, 0.0, 0.5, 1.0}), plan.evaluations);
  std::vector<std::size_t> flank;
  for (std::size_t i : {kStiffness, kDamping}) {
    if (s.free[i]) flank.push_back(i);
  }
  if (!flank.empty()) {
    const SearchResult a = run_search(s, u0, flank, 10.0 * p.step_tolerance);
    plan.evaluations += a.evaluations;
    u0 = a.u;
  }
  if (s.free[kPlay]) scan(s, u0, kPlay, decades(u0, kPlay, {-2.0, -1.5, -1.0, -0.5, 0.0, 0.5}), plan.evaluations);
  if (s.free[kCoulomb]) scan(s, u0, kCoulomb, {u0[kCoulomb], 0.0, 0.01, 0.03, 0.1, 0.3, 1.0}, plan.evaluations);
  scale_steps(s, u0, plan.evaluations);
  plan.u0 = u0;
  plan.start_model = model_of(s, u0);
  plan.start_rms = rms_error(s, plan.start_model);
  ++plan.evaluations;
  for (std::size_t i : {kStiffness, kDamping, kPlay, kCoulomb, kViscous}) {
    if (s.free[i]) plan.active.push_back(i);
  }
  plan.final_active = plan.active;
  if (s.free[kExponent]) plan.final_active.push_back(kExponent);
  return plan;
}

// --- Run ----------------------------------------------------------------------------------

struct FitRun {
  SearchResult best;
  std::vector<ClearanceFitStart> starts;   // every local search after the plan, in order
  int evaluations = 0;
};

void record_start(FitRun& run, const SearchResult& r, double exponent, bool exponent_free) {
  run.evaluations += r.evaluations;
  run.starts.push_back({exponent, exponent_free, r.rms, r.evaluations, nlopt_result_to_string(r.status)});
}

// One search per exponent of the grid (n held), in parallel; the best is kept.
void grid_searches(const FitPlan& plan, FitRun& run) {
  const double tolerance = 10.0 * plan.s.p->step_tolerance;
  std::vector<std::future<SearchResult>> jobs;
  for (double n : plan.grid) {
    Vars u = plan.u0;
    u[kExponent] = n;
    jobs.push_back(std::async(std::launch::async, [&plan, u, tolerance] { return run_search(plan.s, u, plan.active, tolerance); }));
  }
  run.best.rms = std::numeric_limits<double>::infinity();
  for (std::size_t g = 0; g < jobs.size(); ++g) {
    const SearchResult r = jobs[g].get();
    record_start(run, r, plan.grid[g], false);
    if (r.rms < run.best.rms) run.best = r;
  }
}

// Basin hops in the play (its error landscape has side minima where impacts fall a period
// apart): re-scan it about the optimum and search again from a better point, at most twice.
void basin_hops(const FitPlan& plan, FitRun& run) {
  const Setup& s = plan.s;
  for (int hop = 0; hop < 2; ++hop) {
    Vars trial = run.best.u;
    double trial_rms = run.best.rms;
    for (double e : {-1.0, -0.5, -0.25, 0.25, 0.5}) {
      Vars u = run.best.u;
      u[kPlay] = std::clamp(run.best.u[kPlay] + e * std::log(10.0), s.lower[kPlay], s.upper[kPlay]);
      ++run.evaluations;
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
    if (!(trial_rms < run.best.rms)) break;
    const SearchResult hopped = run_search(s, trial, plan.final_active, s.p->step_tolerance);
    record_start(run, hopped, hopped.u[kExponent], s.free[kExponent]);
    if (!(hopped.rms < run.best.rms)) break;
    run.best = hopped;
  }
}

// The searches: the grid, then the sensor bandwidth fixed at the best grid point and a final
// search (n free when it is) on that smooth objective, which decides convergence; basin hops.
FitRun run_fit(FitPlan& plan) {
  FitRun run;
  grid_searches(plan, run);
  Setup& s = plan.s;
  const bool profiled = s.low_pass_hz < 0.0;
  if (profiled) {
    s.low_pass_hz = choose_low_pass(s, model_of(s, run.best.u), nullptr);
    ++run.evaluations;
  }
  if (profiled || plan.final_active.size() > plan.active.size()) {
    const SearchResult refined = run_search(s, run.best.u, plan.final_active, s.p->step_tolerance);
    record_start(run, refined, refined.u[kExponent], s.free[kExponent]);
    run.best = refined;
  }
  if (s.free[kPlay]) basin_hops(plan, run);
  return run;
}

// --- Tabulate -----------------------------------------------------------------------------

double value_of(const ClearanceModel& m, std::size_t i) {
  switch (i) {
    case kStiffness: return m.stiffness;
    case kDamping: return m.contact_law == ContactLawChoice::flores ? m.restitution : m.damping;
    case kPlay: return m.play_rad;
    case kExponent: return m.exponent;
    case kCoulomb: return m.coulomb_n_m;
    default: return m.viscous_n_m_s_per_rad;
  }
}

// Parameter i at the optimum with its 1σ (`se`: of the variables final_active, in that order).
ClearanceParameter describe_parameter(const FitPlan& plan, const FitRun& run, const ClearanceModel& m, std::size_t i,
                                      const std::vector<double>& se) {
  const Setup& s = plan.s;
  const Vars& u = run.best.u;
  ClearanceParameter q;
  q.name = param_name(s, i);
  q.value = value_of(m, i);
  q.start = value_of(plan.start_model, i);
  q.free = s.free[i];
  q.std_error = std::numeric_limits<double>::quiet_NaN();
  if (!q.free) return q;
  const double tol = 1e-6 * (s.upper[i] - s.lower[i]);
  // n >= 1 is Eq. 4.3's own domain and friction >= 0 the law's: a fit on them is a finding, not
  // a search cut short.
  const bool domain_limit = (i == kExponent && s.lower[i] <= 1.0) || i == kCoulomb || i == kViscous;
  q.at_bound = (u[i] <= s.lower[i] + tol && !domain_limit) || u[i] >= s.upper[i] - tol;
  const auto it = std::find(plan.final_active.begin(), plan.final_active.end(), i);
  if (it != plan.final_active.end()) q.std_error = se[static_cast<std::size_t>(it - plan.final_active.begin())];
  // The friction variables and e are linear: 1σ relative to the value (undefined at 0).
  if (i == kCoulomb || i == kViscous || q.name == "restitution") {
    q.std_error = u[i] > 0.0 ? q.std_error / u[i] : std::numeric_limits<double>::quiet_NaN();
  }
  q.identifiable = std::isfinite(q.std_error) && q.std_error < 0.1;
  return q;
}

ClearanceFitResult tabulate_fit(const FitPlan& plan, const FitRun& run) {
  const Setup& s = plan.s;
  const ClearanceFitProblem& p = *s.p;
  ClearanceFitResult out;
  out.reference_deflection_rad = s.delta_ref_rad;
  out.start_model = plan.start_model;
  out.start_rms_error_deg_s = plan.start_rms;
  out.starts = run.starts;
  out.sensor_low_pass_hz = s.low_pass_hz;
  choose_low_pass(s, model_of(s, run.best.u), &out.sensor_low_pass_scan);
  out.model = model_of(s, run.best.u);
  out.rms_error_deg_s = run.best.rms;
  out.evaluations = plan.evaluations + run.evaluations;
  out.termination = nlopt_result_to_string(run.best.status);
  out.converged = is_convergence(run.best.status);
  {
    const auto rate = sensed_link_rate_deg_s(p, simulate_drive_command(out.model, p.drive_command, p.duration_s), s.low_pass_hz);
    const std::vector<double> measured(p.measured_link_rate_deg_s.begin(),
                                       p.measured_link_rate_deg_s.begin() + static_cast<std::ptrdiff_t>(s.samples));
    out.agreement = clearance_agreement(measured, rate);
    if (!p.measured_link_rate_envelope_deg_s.empty()) {  // the objective mixed both: report them apart
      std::vector<double> r(s.samples, 0.0), e(s.samples, 0.0);
      const std::vector<double> env = rate_envelope_deg_s(rate, p.envelope_window_s, p.drive_command.sample_time_s);
      for (std::size_t k = 0; k < s.samples; ++k) {
        r[k] = (k < rate.size() ? rate[k] : 0.0) - measured[k];
        e[k] = (k < env.size() ? env[k] : 0.0) - p.measured_link_rate_envelope_deg_s[k];
      }
      out.rms_error_deg_s = rms(r);
      out.envelope_rms_error_deg_s = rms(e);
    }
  }
  const std::vector<double> se = std_errors(s, run.best.u, plan.final_active);
  for (std::size_t i = 0; i < kParams; ++i) out.parameters.push_back(describe_parameter(plan, run, out.model, i, se));
  return out;
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
  if (name == "exponent" || name == "restitution") return "1";
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

std::vector<double> rate_envelope_deg_s(const std::vector<double>& rate, double window_s, double sample_time_s,
                                        double noise_variance) {
  require_positive("envelope_window_s", window_s);
  require_positive("sample_time_s", sample_time_s);
  const std::size_t n = rate.size();
  const auto half = static_cast<std::size_t>(std::llround(0.5 * window_s / sample_time_s));
  std::vector<double> prefix(n + 1, 0.0);  // prefix sums of the squares: each window in O(1)
  for (std::size_t k = 0; k < n; ++k) prefix[k + 1] = prefix[k] + rate[k] * rate[k];
  std::vector<double> out(n, 0.0);
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t lo = k > half ? k - half : 0, hi = std::min(n, k + half + 1);
    const double ms = (prefix[hi] - prefix[lo]) / static_cast<double>(hi - lo);
    out[k] = std::sqrt(std::max(0.0, ms - noise_variance));
  }
  return out;
}

std::vector<double> mean_rate_envelope_deg_s(const std::vector<std::vector<double>>& records, std::size_t samples,
                                             double window_s, double sample_time_s, std::size_t rest_samples) {
  if (records.empty()) throw InvalidArgument("mean_rate_envelope_deg_s: no records; allowed: at least one");
  std::vector<double> mean(samples, 0.0);
  for (const auto& r : records) {
    if (r.size() < samples) throw_invalid("record samples", static_cast<double>(r.size()), fmt::format(">= {}", samples));
    double variance = 0.0;
    if (rest_samples > 1) {  // the rest's scatter about its mean (the gyro bias is not motion)
      const std::size_t m = std::min(rest_samples, samples);
      double sum = 0.0, sq = 0.0;
      for (std::size_t k = 0; k < m; ++k) sum += r[k];
      for (std::size_t k = 0; k < m; ++k) sq += (r[k] - sum / static_cast<double>(m)) * (r[k] - sum / static_cast<double>(m));
      variance = sq / static_cast<double>(m - 1);
    }
    const std::vector<double> head(r.begin(), r.begin() + static_cast<std::ptrdiff_t>(samples));
    const std::vector<double> e = rate_envelope_deg_s(head, window_s, sample_time_s, variance);
    for (std::size_t k = 0; k < samples; ++k) mean[k] += e[k] / static_cast<double>(records.size());
  }
  return mean;
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
  FitPlan plan = plan_fit(p);
  const FitRun run = run_fit(plan);
  return tabulate_fit(plan, run);
}

}  // namespace clearshape::study
