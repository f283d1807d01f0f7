// The per-run joint fit (study/model.hpp fit_clearance_runs; issue 19, docs/worn-coupling.md).
// Runs whose links started at different places in the play are never averaged: every run keeps
// its own start place s_i = φ_i(0)/β as a nuisance parameter (and, by default, its own flank
// damping D_i: the rig's lubrication varies from run to run, rig/variation.hpp), and the joint's
// parameters θ (K, play, Coulomb c, viscous b; n held) are shared. In three steps:
//   scan        the sensor bandwidth, then the play over a log grid and the Coulomb torque over
//               multiples of the record's scale, each with every s_i profiled over a grid
//   refine      Levenberg–Marquardt (Marquardt 1963) on (θ, s_i, D_i), finite-difference
//               Jacobian: a column of θ costs one simulation per run, all s_i together one more
//               (run i's residual depends on its own s_i alone), all D_i together one more
//   tabulate    1σ: the larger of σ²(JᵀJ)⁻¹ (σ² AR(1)-inflated) and the run-clustered sandwich
//               (JᵀJ)⁻¹(Σ_i J_iᵀr_i r_iᵀJ_i)(JᵀJ)⁻¹; the n-free alternative as a score test at n = 1;
//               the optimum re-simulated with CVODE
// The inner loop is the fixed-step simulator (plant/fixed_step.hpp, via simulate_drive_command's
// design accuracy) for the linear dashpot flank; the final check is CVODE.
#include <algorithm>
#include <array>
#include <cmath>
#include <future>
#include <limits>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "clearshape/core/distributions.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::study {

namespace {

// Shared parameters, in ClearanceParameter order (the exponent is held; its freedom is tested).
// kF: the gyro's first-order low-pass bandwidth, fitted continuously when the problem offers a
// choice (its grid only starts it; 0 = none is read as 1 kHz, a = 0.998 at 1 kHz sampling).
enum Shared : std::size_t { kK = 0, kD = 1, kPlay = 2, kN = 3, kC = 4, kB = 5, kF = 6 };
constexpr std::size_t kShared = 7;
constexpr std::size_t kParameters = 6;  // those written as ClearanceParameter (not kF)
constexpr std::array<const char*, kShared> kNames{"stiffness", "damping", "play", "exponent", "coulomb", "viscous",
                                                   "sensor_low_pass"};
constexpr double kNoFilterHz = 1000.0;
// The start grid of the profiles and hops (φ(0)/β).
constexpr std::array<double, 17> kStartGrid{-1.0, -0.875, -0.75, -0.625, -0.5, -0.375, -0.25, -0.125, 0.0,
                                             0.125, 0.25, 0.375, 0.5, 0.625, 0.75, 0.875, 1.0};
constexpr double kStartStep = 0.02;  // the starts' difference step

using Theta = std::array<double, kShared>;  // log K, log D, log play, n, c/c_scale, b/b_scale, log f_c

// Each run's nuisance variables: its start φ(0)/β and (per-run damping) its log D.
struct Runs {
  std::vector<double> start;
  std::vector<double> log_damping;
};

struct Fit {
  const ClearanceRunsFitProblem* p = nullptr;
  std::size_t samples = 0;
  std::vector<std::vector<double>> measured;  // per run, bias removed
  std::vector<std::size_t> active;            // fitted shared parameters
  bool per_run_damping = false;
  double c_scale = 1.0, b_scale = 1.0;        // c = c_scale·x, b = b_scale·x
  double low_pass_hz = 0.0;  // the bandwidth when it is not fitted
  int simulations = 0;
  Theta theta{}, lower{}, upper{}, fd_step{};
  std::size_t full_samples = 0;               // over duration_s
  std::size_t move_sample = 0;                // the first sample where any run's command moves
  double sample_time_s = 1e-3;
  std::size_t runs() const { return measured.size(); }
  double window_s() const { return static_cast<double>(samples - 1) * sample_time_s; }
  std::size_t per_run_columns() const { return per_run_damping ? 2 : 1; }
};

ClearanceModel model_of(const Fit& f, const Theta& t) {
  ClearanceModel m = f.p->start;
  m.stiffness = std::exp(t[kK]);
  m.damping = std::exp(t[kD]);
  m.play_rad = std::exp(t[kPlay]);
  m.exponent = t[kN];
  m.coulomb_n_m = f.c_scale * t[kC];
  m.viscous_n_m_s_per_rad = f.b_scale * t[kB];
  return m;
}

ClearanceModel run_model(const Fit& f, const Theta& t, const Runs& v, std::size_t i) {
  ClearanceModel m = model_of(f, t);
  if (f.per_run_damping) m.damping = std::exp(v.log_damping[i]);
  return m;
}

struct Job {
  ClearanceModel model;
  std::size_t run = 0;
  double start = 0.0;
  double hz = 0.0;  // the gyro low-pass; NaN: return the raw link rate (no filter, no record subtracted)
};

double bandwidth(const Fit& f, const Theta& t) {
  return std::find(f.active.begin(), f.active.end(), kF) != f.active.end() ? std::exp(t[kF]) : f.low_pass_hz;
}

Job job(const Fit& f, const Theta& t, const Runs& v, std::size_t i, double start) {
  return {run_model(f, t, v, i), i, start, bandwidth(f, t)};
}

// The residuals (gyro view of the model − measured) of the jobs, simulated on f.p->threads
// workers with a fixed job-to-worker assignment (the result does not depend on the thread
// count). The gyro's view: the link rate through its first-order low-pass (y += a(x − y),
// a = 1 − exp(−2π f_c T), plant/gyroscope.hpp). An integration failure gives an empty residual.
// Job j's residual from its simulated response (its link rate, low-passed like the gyro, less
// the record); empty when the simulation failed.
std::vector<double> residual_of(const Fit& f, const Job& job, ModelResponse& r) {
  std::vector<double>& rate = r.link_rate_deg_s;
  rate.resize(f.samples, rate.empty() ? 0.0 : rate.back());
  if (!std::isnan(job.hz)) {
    apply_sensor_low_pass(rate, job.hz, f.p->runs[job.run].drive_command.sample_time_s);
    const auto& y = f.measured[job.run];
    for (std::size_t k = 0; k < rate.size(); ++k) rate[k] -= y[k];
  }
  return std::move(rate);
}

// Every job's residual, in parallel: worker w takes the pairs of jobs (2q, 2q + 1) for q = w,
// w + W, …, a pair simulated together at the design's accuracy (simulate_drive_commands); the fit's
// final check (design_accuracy false, CVODE) one job at a time.
std::vector<std::vector<double>> residuals(Fit& f, const std::vector<Job>& jobs, bool design_accuracy = true) {
  std::vector<std::vector<double>> out(jobs.size());
  const auto workers = static_cast<std::size_t>(std::clamp(f.p->threads, 1, 64));
  const auto one = [&](std::size_t j) {
    try {
      const auto& rec = f.p->runs[jobs[j].run];
      ModelResponse r = simulate_drive_command(jobs[j].model, rec.drive_command, f.window_s(),
                                               std::clamp(jobs[j].start, -1.0, 1.0), design_accuracy);
      out[j] = residual_of(f, jobs[j], r);
    } catch (const std::exception&) {
      out[j].clear();
    }
  };
  const auto pair = [&](std::size_t j0, std::size_t j1) {
    std::vector<DriveCommandJob> batch;
    for (std::size_t j = j0; j < j1; ++j) {
      batch.push_back({&jobs[j].model, &f.p->runs[jobs[j].run].drive_command, f.window_s(), std::clamp(jobs[j].start, -1.0, 1.0)});
    }
    std::vector<DriveCommandOutcome> outcomes = simulate_drive_commands(batch);
    for (std::size_t j = j0; j < j1; ++j) {
      try {
        if (outcomes[j - j0].error) std::rethrow_exception(outcomes[j - j0].error);
        out[j] = residual_of(f, jobs[j], outcomes[j - j0].response);
      } catch (const std::exception&) {
        out[j].clear();  // a failed simulation: no information
      }
    }
  };
  const auto work = [&](std::size_t w) {
    if (!design_accuracy) {
      for (std::size_t j = w; j < jobs.size(); j += workers) one(j);
      return;
    }
    for (std::size_t j = 2 * w; j < jobs.size(); j += 2 * workers) pair(j, std::min(j + 2, jobs.size()));
  };
  std::vector<std::future<void>> pool;
  for (std::size_t w = 1; w < workers; ++w) pool.push_back(std::async(std::launch::async, work, w));
  work(0);
  for (auto& t : pool) t.get();
  f.simulations += static_cast<int>(jobs.size());
  return out;
}

double ssr_of(const std::vector<double>& r) {
  if (r.empty()) return std::numeric_limits<double>::infinity();
  double s = 0.0;
  for (double e : r) s += e * e;
  return s;
}

// Every run at (θ, v): the stacked residual's sum of squares (∞ on a failure).
double total_ssr(Fit& f, const Theta& t, const Runs& v, std::vector<std::vector<double>>* out = nullptr) {
  std::vector<Job> jobs;
  for (std::size_t i = 0; i < f.runs(); ++i) jobs.push_back(job(f, t, v, i, v.start[i]));
  auto r = residuals(f, jobs);
  double total = 0.0;
  for (const auto& ri : r) total += ssr_of(ri);
  if (out) *out = std::move(r);
  return total;
}

// The per-run profile grid: every start of kStartGrid, and with per-run damping every factor of
// kDampingGrid on the runs' geometric-mean D (the rig's D varies by σ(ln D) ≈ 0.2 from run to run).
constexpr std::array<double, 5> kDampingGrid{0.6, 0.8, 1.0, 1.25, 1.6};

struct GridPoint {
  double start = 0.0;
  double log_damping = 0.0;
};

std::vector<GridPoint> run_grid(const Fit& f, const Runs& v, bool with_damping, std::size_t start_stride) {
  double centre = 0.0;
  for (double d : v.log_damping) centre += d / static_cast<double>(v.log_damping.size());
  std::vector<GridPoint> grid;
  for (std::size_t k = 0; k < kStartGrid.size(); k += start_stride) {
    const double s = kStartGrid[k];
    if (!(with_damping && f.per_run_damping)) {
      grid.push_back({s, std::numeric_limits<double>::quiet_NaN()});
      continue;
    }
    for (double d : kDampingGrid) grid.push_back({s, centre + std::log(d)});
  }
  return grid;
}

// Profiles the nuisances of the first `count` runs over the grid at θ (runs are independent given
// θ; every `start_stride`-th start): the best grid point of each replaces its nuisances when it
// beats `keep[i]` (empty: always); the summed SSR of those runs. With `hz` given, the gyro
// bandwidth is profiled too (over the problem's grid, shared by the runs) and returned there.
// `angle`: the misfit of the link angle (the rate residual's running sum × T) — far smoother in
// the parameters than the rate's, whose rebounds alias a period away: the scans use it.
double profile_runs(Fit& f, const Theta& t, Runs& v, bool with_damping, const std::vector<double>& keep = {},
                    std::size_t count = std::numeric_limits<std::size_t>::max(), std::size_t start_stride = 1,
                    double* hz = nullptr, bool angle = false) {
  count = std::min(count, f.runs());
  const std::vector<GridPoint> grid = run_grid(f, v, with_damping, start_stride);
  std::vector<Job> jobs;
  for (std::size_t i = 0; i < count; ++i) {
    for (const GridPoint& g : grid) {
      Runs trial = v;
      if (std::isfinite(g.log_damping)) trial.log_damping[i] = g.log_damping;
      jobs.push_back({run_model(f, t, trial, i), i, g.start, std::numeric_limits<double>::quiet_NaN()});
    }
  }
  const auto rates = residuals(f, jobs);
  const std::vector<double> bands = hz ? f.p->sensor_low_pass_grid_hz : std::vector<double>{bandwidth(f, t)};
  double best_total = std::numeric_limits<double>::infinity();
  Runs best_v = v;
  for (double band : bands) {
    Runs trial = v;
    double total = 0.0;
    for (std::size_t i = 0; i < count; ++i) {
      double best = keep.empty() ? std::numeric_limits<double>::infinity() : keep[i];
      for (std::size_t g = 0; g < grid.size(); ++g) {
        std::vector<double> r = rates[i * grid.size() + g];
        if (r.empty()) continue;
        apply_sensor_low_pass(r, band, f.p->runs[i].drive_command.sample_time_s);
        for (std::size_t k = 0; k < r.size(); ++k) r[k] -= f.measured[i][k];
        if (angle) {
          double sum = 0.0;
          for (double& e : r) e = (sum += e * f.sample_time_s);
        }
        const double e = ssr_of(r);
        if (e < best) {
          best = e;
          trial.start[i] = grid[g].start;
          if (std::isfinite(grid[g].log_damping)) trial.log_damping[i] = grid[g].log_damping;
        }
      }
      total += best;
    }
    if (total < best_total) {
      best_total = total;
      best_v = trial;
      if (hz) *hz = band;
    }
  }
  v = best_v;
  return best_total;
}

// Configuration-time checks that need no simulation (InvalidArgument naming the field).
void validate(const ClearanceRunsFitProblem& p) {
  if (p.runs.empty()) throw InvalidArgument("clearance runs fit: runs is empty; allowed: at least one record");
  require_positive("duration_s", p.duration_s);
  require_non_negative("rest_s", p.rest_s);
  require_positive("start.link_inertia_kg_m2", p.start.link_inertia_kg_m2);
  require_positive("start.stiffness", p.start.stiffness);
  require_positive("start.damping", p.start.damping);
  require_positive("start.play_rad", p.start.play_rad, "the per-run fit needs a play to fit");
  require_in_closed("start.exponent", p.start.exponent, 1.0, 10.0);
  require_non_negative("start.coulomb_n_m", p.start.coulomb_n_m);
  require_non_negative("start.viscous_n_m_s_per_rad", p.start.viscous_n_m_s_per_rad);
  if (p.start.contact_law != ContactLawChoice::dashpot) {
    throw InvalidArgument("clearance runs fit: start.contact_law is 'flores'; allowed: dashpot (Eq. 4.3)");
  }
  if (p.max_iterations < 1) throw_invalid("max_iterations", p.max_iterations, ">= 1");
  if (p.sensor_low_pass_grid_hz.empty()) {
    throw InvalidArgument("clearance runs fit: sensor_low_pass_grid_hz is empty; allowed: at least one bandwidth (0 = none)");
  }
  for (double hz : p.sensor_low_pass_grid_hz) require_non_negative("sensor_low_pass_grid_hz", hz);
}

// The records with their resting bias removed (the gyro's mean before the move); the peak |rate|.
double load_records(const ClearanceRunsFitProblem& p, Fit& f) {
  const double ts = p.runs.front().drive_command.sample_time_s;
  require_positive("runs[0].drive_command.sample_time_s", ts);
  f.samples = sample_count(p.duration_s, ts);
  f.full_samples = f.samples;
  f.sample_time_s = ts;
  f.move_sample = f.samples;
  for (const auto& r : p.runs) {
    for (std::size_t k = 1; k < f.samples && k < f.move_sample; ++k) {
      if (r.drive_command.values[k] != r.drive_command.values.front()) f.move_sample = k;
    }
  }
  const auto rest = static_cast<std::size_t>(std::floor(p.rest_s / ts));
  double peak_rad_s = 0.0;
  for (std::size_t i = 0; i < p.runs.size(); ++i) {
    const auto& r = p.runs[i];
    if (r.drive_command.sample_time_s != ts) {
      throw_invalid(fmt::format("runs[{}].drive_command.sample_time_s", i), r.drive_command.sample_time_s,
                    fmt::format("{} (the first run's)", ts));
    }
    if (r.link_rate_deg_s.size() < f.samples || r.drive_command.values.size() < f.samples) {
      throw_invalid(fmt::format("runs[{}] samples", i),
                    static_cast<double>(std::min(r.link_rate_deg_s.size(), r.drive_command.values.size())),
                    fmt::format(">= {} (duration_s)", f.samples));
    }
    double bias = 0.0;
    for (std::size_t k = 0; k < rest && k < f.samples; ++k) bias += r.link_rate_deg_s[k] / static_cast<double>(rest);
    std::vector<double> y(r.link_rate_deg_s.begin(), r.link_rate_deg_s.begin() + static_cast<std::ptrdiff_t>(f.samples));
    for (double& v : y) {
      v -= bias;
      peak_rad_s = std::max(peak_rad_s, std::abs(deg_to_rad(v)));
    }
    f.measured.push_back(std::move(y));
  }
  return peak_rad_s;
}

// Validation, records, start values, bounds and scales; the runs' nuisances at their starts.
Fit plan(const ClearanceRunsFitProblem& p, Runs& v) {
  validate(p);
  Fit f;
  f.p = &p;
  const double peak_rad_s = load_records(p, f);
  for (const auto& name : p.free) {
    const auto it = std::find(kNames.begin(), kNames.end(), name);
    if (it == kNames.end() || name == "exponent") {
      throw InvalidArgument(fmt::format("clearance runs fit: '{}' cannot be fitted; allowed: stiffness, damping, play, "
                                        "coulomb, viscous (n is held; its freedom is tested)",
                                        name));
    }
    f.active.push_back(static_cast<std::size_t>(it - kNames.begin()));
  }
  std::sort(f.active.begin(), f.active.end());
  f.active.erase(std::unique(f.active.begin(), f.active.end()), f.active.end());
  const auto d_free = std::find(f.active.begin(), f.active.end(), kD);
  f.per_run_damping = p.per_run_damping && d_free != f.active.end();
  if (f.per_run_damping) f.active.erase(d_free);  // each run's own D instead
  f.low_pass_hz = p.sensor_low_pass_grid_hz.front();
  if (p.sensor_low_pass_grid_hz.size() > 1) f.active.push_back(kF);
  // Scales: c in J·a_ref (a_ref = peak |ω| / T, the deceleration that stops the fastest link
  // motion within the window), b in J/T.
  const double J = p.start.link_inertia_kg_m2;
  f.c_scale = J * std::max(peak_rad_s, 1e-3) / p.duration_s;
  f.b_scale = J / p.duration_s;
  const double w = p.link_natural_frequency_rad_s;
  // A linear flank from the link mode: K = J ω², D = 2ζωJ (single-DOF oscillator).
  const double k0 = w > 0.0 ? J * w * w : p.start.stiffness;
  const double d0 = w > 0.0 && p.link_damping_ratio > 0.0 ? 2.0 * p.link_damping_ratio * w * J : p.start.damping;
  f.theta = {std::log(k0), std::log(d0), std::log(p.start.play_rad), p.start.exponent,
             p.start.coulomb_n_m > 0.0 ? p.start.coulomb_n_m / f.c_scale : 1.0, p.start.viscous_n_m_s_per_rad / f.b_scale,
             std::log(f.low_pass_hz > 0.0 ? f.low_pass_hz : kNoFilterHz)};
  if (std::find(f.active.begin(), f.active.end(), kC) == f.active.end()) f.theta[kC] = p.start.coulomb_n_m / f.c_scale;
  f.lower = {f.theta[kK] - std::log(1e3), f.theta[kD] - std::log(1e3), std::log(deg_to_rad(0.005)), 1.0, 0.0, 0.0, std::log(2.0)};
  f.upper = {f.theta[kK] + std::log(1e3), f.theta[kD] + std::log(1e3), std::log(deg_to_rad(10.0)), 10.0, 100.0, 100.0,
             std::log(kNoFilterHz)};
  f.fd_step = {0.02, 0.02, 0.01, 0.05, 0.02, 0.05, 0.02};
  for (std::size_t i = 0; i < kShared; ++i) f.theta[i] = std::clamp(f.theta[i], f.lower[i], f.upper[i]);
  v.start.assign(f.runs(), 0.0);
  v.log_damping.assign(f.runs(), f.theta[kD]);
  return f;
}

bool is_active(const Fit& f, std::size_t i) { return std::find(f.active.begin(), f.active.end(), i) != f.active.end(); }

// The coarse scans, on the first kScanRuns runs with every other start of the grid profiled:
// K (× 1/4 … 4 about its start, factors of √2) by the play (0.03–4°, factors of 2), each run's
// start profiled; the kScanStarts best grid points are kept (the angle misfit of a 0.25 s window
// can rank a wrong (K, play) pair first by a fraction of a percent). From each: the Coulomb torque
// over 0 and 1/4 … 4 × its start, then every run's start and damping profiled.
constexpr std::size_t kScanRuns = 3;
constexpr std::size_t kScanStarts = 3;

struct ScanPoint {
  double error = 0.0;
  Theta theta{};
  Runs runs;
};

ScanPoint scan_point(Fit& f, Theta t, const Runs& v) {
  ScanPoint p{0.0, t, v};
  double hz = 0.0;
  const bool fit_band = is_active(f, kF);
  p.error = profile_runs(f, t, p.runs, false, {}, kScanRuns, 2, fit_band ? &hz : nullptr, true);
  if (fit_band) p.theta[kF] = std::log(hz > 0.0 ? hz : kNoFilterHz);
  return p;
}

std::vector<ScanPoint> scan_grid(Fit& f, const Runs& v) {
  const std::vector<double> k_factors = is_active(f, kK) ? std::vector<double>{0.25, 0.35, 0.5, 0.7, 1.0, 1.4, 2.0, 2.8, 4.0} : std::vector<double>{1.0};
  const std::vector<double> plays = is_active(f, kPlay) ? std::vector<double>{0.03, 0.06, 0.12, 0.25, 0.5, 1.0, 2.0, 4.0}
                                                        : std::vector<double>{rad_to_deg(std::exp(f.theta[kPlay]))};
  std::vector<ScanPoint> points;
  for (double kf : k_factors) {
    for (double deg : plays) {
      Theta t = f.theta;
      t[kK] = std::clamp(f.theta[kK] + std::log(kf), f.lower[kK], f.upper[kK]);
      t[kPlay] = std::clamp(std::log(deg_to_rad(deg)), f.lower[kPlay], f.upper[kPlay]);
      points.push_back(scan_point(f, t, v));
    }
  }
  std::stable_sort(points.begin(), points.end(), [](const ScanPoint& a, const ScanPoint& b) { return a.error < b.error; });
  points.resize(std::min(points.size(), kScanStarts));
  return points;
}

void scan_friction(Fit& f, Runs& v, const ScanPoint& from) {
  ScanPoint best = from;
  if (is_active(f, kC)) {
    for (double factor : {0.0, 0.25, 0.5, 2.0, 4.0}) {
      Theta t = from.theta;
      t[kC] = std::min(from.theta[kC] * factor, f.upper[kC]);
      ScanPoint p = scan_point(f, t, from.runs);
      if (p.error < best.error) best = std::move(p);
    }
  }
  f.theta = best.theta;
  v = best.runs;
  profile_runs(f, f.theta, v, true);
}

// The stacked Jacobian of the residual in (θ_active, s_1…s_N[, log D_1…log D_N]) by forward
// differences: one batch per θ column (every run), one batch for all starts together, one for all
// dampings (run i's rows depend on its own nuisances alone).
Eigen::MatrixXd jacobian(Fit& f, const Runs& v, const std::vector<std::vector<double>>& base) {
  const std::size_t n = f.runs(), m = f.samples, p = f.active.size(), q = f.per_run_columns();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n * m), static_cast<Eigen::Index>(p + q * n));
  std::vector<Job> jobs;
  std::vector<double> h;  // per batch and run
  for (std::size_t c = 0; c < p; ++c) {
    Theta tp = f.theta;
    const std::size_t i = f.active[c];
    const double step = f.theta[i] + f.fd_step[i] <= f.upper[i] ? f.fd_step[i] : -f.fd_step[i];
    tp[i] += step;
    for (std::size_t r = 0; r < n; ++r) {
      jobs.push_back(job(f, tp, v, r, v.start[r]));
      h.push_back(step);
    }
  }
  for (std::size_t r = 0; r < n; ++r) {
    const double step = v.start[r] + kStartStep <= 1.0 ? kStartStep : -kStartStep;
    jobs.push_back(job(f, f.theta, v, r, v.start[r] + step));
    h.push_back(step);
  }
  if (f.per_run_damping) {
    for (std::size_t r = 0; r < n; ++r) {
      Runs vp = v;
      const double step = v.log_damping[r] + f.fd_step[kD] <= f.upper[kD] ? f.fd_step[kD] : -f.fd_step[kD];
      vp.log_damping[r] += step;
      jobs.push_back(job(f, f.theta, vp, r, v.start[r]));
      h.push_back(step);
    }
  }
  const auto res = residuals(f, jobs);
  for (std::size_t j = 0; j < jobs.size(); ++j) {
    const std::size_t batch = j / n, r = jobs[j].run;
    if (res[j].empty() || base[r].empty()) continue;  // a failed simulation: no information
    const auto col = static_cast<Eigen::Index>(batch < p ? batch : p + (batch - p) * n + r);
    for (std::size_t k = 0; k < m; ++k) J(static_cast<Eigen::Index>(r * m + k), col) = (res[j][k] - base[r][k]) / h[j];
  }
  return J;
}

Eigen::VectorXd stack(const std::vector<std::vector<double>>& r, std::size_t m) {
  Eigen::VectorXd v(static_cast<Eigen::Index>(r.size() * m));
  for (std::size_t i = 0; i < r.size(); ++i) {
    for (std::size_t k = 0; k < m; ++k) v(static_cast<Eigen::Index>(i * m + k)) = r[i].empty() ? 0.0 : r[i][k];
  }
  return v;
}

struct Refined {
  std::vector<std::vector<double>> residual;
  Eigen::MatrixXd J;  // at the optimum
  double ssr = 0.0;
  int iterations = 0;
  bool converged = false;
  std::string termination;
};

// One damped step δ from (θ, v) clamped to the bounds; `scaled` receives max |δ_j| / (its
// difference step).
void apply_step(const Fit& f, const Eigen::VectorXd& delta, Theta& t, Runs& v, double& scaled) {
  const std::size_t p = f.active.size(), n = f.runs();
  scaled = 0.0;
  for (std::size_t c = 0; c < p; ++c) {
    const std::size_t i = f.active[c];
    const double x = std::clamp(t[i] + delta(static_cast<Eigen::Index>(c)), f.lower[i], f.upper[i]);
    scaled = std::max(scaled, std::abs(x - t[i]) / f.fd_step[i]);
    t[i] = x;
  }
  for (std::size_t r = 0; r < n; ++r) {
    const double x = std::clamp(v.start[r] + delta(static_cast<Eigen::Index>(p + r)), -1.0, 1.0);
    scaled = std::max(scaled, std::abs(x - v.start[r]) / kStartStep);
    v.start[r] = x;
    if (f.per_run_damping) {
      const double d = std::clamp(v.log_damping[r] + delta(static_cast<Eigen::Index>(p + n + r)), f.lower[kD], f.upper[kD]);
      scaled = std::max(scaled, std::abs(d - v.log_damping[r]) / f.fd_step[kD]);
      v.log_damping[r] = d;
    }
  }
}

// Levenberg–Marquardt (Marquardt 1963: (JᵀJ + λ·diag JᵀJ) δ = −Jᵀr), projected on the bounds.
Refined refine(Fit& f, Runs& v) {
  Refined out;
  out.ssr = total_ssr(f, f.theta, v, &out.residual);
  if (!std::isfinite(out.ssr)) throw RuntimeError("clearance runs fit: the start model's simulation failed");
  double lambda = 1e-3;
  out.termination = "max_iterations";
  for (int it = 0; it < f.p->max_iterations; ++it) {
    out.iterations = it + 1;
    out.J = jacobian(f, v, out.residual);
    const Eigen::VectorXd r = stack(out.residual, f.samples);
    const Eigen::MatrixXd A = out.J.transpose() * out.J;
    const Eigen::VectorXd g = out.J.transpose() * r;
    bool accepted = false;
    double scaled = 0.0;
    for (int attempt = 0; attempt < 8 && !accepted; ++attempt) {
      Eigen::MatrixXd M = A;
      for (Eigen::Index d = 0; d < M.rows(); ++d) M(d, d) += lambda * A(d, d) + 1e-12 * A.diagonal().maxCoeff();
      Theta t = f.theta;
      Runs trial = v;
      apply_step(f, M.ldlt().solve(-g), t, trial, scaled);
      std::vector<std::vector<double>> res;
      const double e = total_ssr(f, t, trial, &res);
      if (e < out.ssr) {
        const double gain = (out.ssr - e) / out.ssr;
        f.theta = t;
        v = trial;
        out.ssr = e;
        out.residual = std::move(res);
        lambda = std::max(lambda * 0.3, 1e-7);
        accepted = true;
        if (gain < 1e-6 || scaled < 1e-3) {
          out.converged = true;
          out.termination = gain < 1e-6 ? "relative decrease below 10⁻⁶" : "step below 10⁻³ of the difference steps";
        }
      } else {
        lambda *= 10.0;
      }
    }
    if (!accepted) {  // no decrease even with a short step: a minimum to the difference steps' accuracy
      out.converged = scaled < 0.1;
      out.termination = "no decrease along the damped step";
    }
    if (!accepted || out.converged) break;
  }
  out.J = jacobian(f, v, out.residual);
  return out;
}

// Hops: each run's nuisances re-profiled over the grid at the optimum (one run's error has side
// minima in its start: a pick-up one flank earlier or later); true when a run's error drops by
// more than 2 %, its nuisances then replaced by the grid's best.
bool hop_runs(Fit& f, const Refined& fit, Runs& v) {
  std::vector<double> keep;
  for (const auto& r : fit.residual) keep.push_back(0.98 * ssr_of(r));
  const Runs before = v;
  profile_runs(f, f.theta, v, true, keep);
  return v.start != before.start || v.log_damping != before.log_damping;
}

// Lag-1 autocorrelation of the residual (per run, pooled), clipped to [0, 0.999].
double lag1(const std::vector<std::vector<double>>& r) {
  double num = 0.0, den = 0.0;
  for (const auto& ri : r) {
    for (std::size_t k = 0; k < ri.size(); ++k) {
      den += ri[k] * ri[k];
      if (k > 0) num += ri[k] * ri[k - 1];
    }
  }
  return den > 0.0 ? std::clamp(num / den, 0.0, 0.999) : 0.0;
}

struct Covariance {
  Eigen::MatrixXd cov;  // of every variable; its diagonal the larger of the two estimates
  double sigma2 = 0.0;  // effective residual variance
  bool ok = false;
};

// σ²(JᵀJ)⁻¹ with σ² = SSR/(N − P)·(1 + ρ)/(1 − ρ) (AR(1) variance factor), and the run-clustered
// sandwich A⁻¹(Σ_i g_i g_iᵀ)A⁻¹·G/(G − 1), g_i = J_iᵀ r_i (Liang & Zeger 1986); per variable the
// larger variance is kept.
Covariance covariance(const Fit& f, const Refined& fit) {
  Covariance c;
  const Eigen::MatrixXd A = fit.J.transpose() * fit.J;
  const linalg::SymmetricEigenDecomposition eig = linalg::symmetric_eigen(A);
  if (!eig.converged || !(eig.values.minCoeff() > 1e-12 * eig.values.maxCoeff())) return c;
  const Eigen::MatrixXd Ainv = A.inverse();
  const double N = static_cast<double>(fit.J.rows()), P = static_cast<double>(fit.J.cols());
  const double rho = lag1(fit.residual);
  c.sigma2 = fit.ssr / std::max(1.0, N - P) * (1.0 + rho) / (1.0 - rho);
  c.cov = c.sigma2 * Ainv;
  const std::size_t runs = f.runs();
  if (runs >= 3) {
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(A.rows(), A.cols());
    const auto m = static_cast<Eigen::Index>(f.samples);
    for (std::size_t i = 0; i < runs; ++i) {
      const Eigen::VectorXd ri = stack({fit.residual[i]}, f.samples);
      const Eigen::VectorXd g = fit.J.middleRows(static_cast<Eigen::Index>(i) * m, m).transpose() * ri;
      B += g * g.transpose();
    }
    const double G = static_cast<double>(runs);
    const Eigen::MatrixXd sandwich = Ainv * B * Ainv * (G / (G - 1.0));
    for (Eigen::Index d = 0; d < A.rows(); ++d) c.cov(d, d) = std::max(c.cov(d, d), sandwich(d, d));
  }
  c.ok = true;
  return c;
}

// The n-free alternative as a score test at n = 1 (the law's own limit): the exponent's column
// (K carried at the reference deflection δ_ref: K·δ_ref^(n−1) held) joins the Jacobian; the
// Gauss–Newton step in n with the others re-fitted, its 1σ, and χ² = (SSR it removes)/σ².
void exponent_score(Fit& f, const Refined& fit, const Runs& v, const Covariance& cov, ClearanceRunsFitResult& out) {
  const ClearanceModel m0 = run_model(f, f.theta, v, 0);
  // δ_ref: the RMS contact deflection |θ_m − θ_l| − β of the first run (it scales K only).
  const ModelResponse r0 = simulate_drive_command(m0, f.p->runs.front().drive_command, f.p->duration_s, v.start.front(), true);
  ++f.simulations;
  double ss = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < r0.link_angle_deg.size(); ++k) {
    const double d = std::abs(deg_to_rad(r0.motor_angle_deg[k] - r0.link_angle_deg[k])) - 0.5 * m0.play_rad;
    if (d > 0.0) {
      ss += d * d;
      ++count;
    }
  }
  const double delta_ref = count > 0 ? std::sqrt(ss / static_cast<double>(count)) : 1e-3;
  const double h = f.fd_step[kN];
  // Both sides through the same integrator: n ≠ 1 (by a hair on the base side) takes CVODE's path.
  std::vector<Job> plus, base;
  for (std::size_t i = 0; i < f.runs(); ++i) {
    ClearanceModel mb = run_model(f, f.theta, v, i);
    ClearanceModel mp = mb;
    mb.exponent += 1e-12;
    mp.exponent += h;
    mp.stiffness *= std::pow(delta_ref, -h);  // K_ref = K·δ_ref^(n−1) held
    plus.push_back({mp, i, v.start[i], bandwidth(f, f.theta)});
    base.push_back({mb, i, v.start[i], bandwidth(f, f.theta)});
  }
  const auto rp = residuals(f, plus), rb = residuals(f, base);
  const auto cols = fit.J.cols();
  Eigen::MatrixXd Ja(fit.J.rows(), cols + 1);
  Ja.leftCols(cols) = fit.J;
  for (std::size_t i = 0; i < f.runs(); ++i) {
    const bool okay = !rp[i].empty() && !rb[i].empty();
    for (std::size_t k = 0; k < f.samples; ++k) {
      Ja(static_cast<Eigen::Index>(i * f.samples + k), cols) = okay ? (rp[i][k] - rb[i][k]) / h : 0.0;
    }
  }
  const Eigen::VectorXd r = stack(fit.residual, f.samples);
  const Eigen::MatrixXd A = Ja.transpose() * Ja;
  const Eigen::VectorXd g = Ja.transpose() * r;
  const Eigen::MatrixXd A0 = fit.J.transpose() * fit.J;
  const Eigen::VectorXd g0 = fit.J.transpose() * r;
  // The SSR a Gauss–Newton step removes: gᵀA⁻¹g with n free minus without it.
  const double removed = g.dot(A.ldlt().solve(g)) - g0.dot(A0.ldlt().solve(g0));
  const double dn = -A.ldlt().solve(g)(cols);
  out.exponent_free_value = m0.exponent + std::max(0.0, dn);
  out.exponent_free_std = cov.ok ? std::sqrt(cov.sigma2 * A.inverse()(cols, cols)) : std::numeric_limits<double>::quiet_NaN();
  out.exponent_chi2 = dn > 0.0 && cov.sigma2 > 0.0 ? std::max(0.0, removed) / cov.sigma2 : 0.0;
  out.exponent_free_better = out.exponent_chi2 > 3.84;  // χ²₁ at 5 %
}

// The fitted model, each parameter with its 1σ, each run's start and damping.
void describe(const Fit& f, const Runs& v, const Covariance& cov, ClearanceRunsFitResult& out) {
  const std::size_t p = f.active.size(), n = f.runs();
  out.model = model_of(f, f.theta);
  // Per-run damping: D the runs' geometric mean, its log-σ the standard error of their scatter.
  double d_sigma = std::numeric_limits<double>::quiet_NaN();
  if (f.per_run_damping) {
    double mean = 0.0, var = 0.0;
    for (double d : v.log_damping) mean += d / static_cast<double>(n);
    for (double d : v.log_damping) var += (d - mean) * (d - mean) / static_cast<double>(std::max<std::size_t>(n - 1, 1));
    out.model.damping = std::exp(mean);
    d_sigma = n > 1 ? std::sqrt(var / static_cast<double>(n)) : std::numeric_limits<double>::quiet_NaN();
  }
  const ClearanceModel& m = out.model;
  const Theta values{m.stiffness, m.damping, m.play_rad, m.exponent, m.coulomb_n_m, m.viscous_n_m_s_per_rad};
  const Theta starts{f.p->start.stiffness, f.p->start.damping, f.p->start.play_rad, f.p->start.exponent,
                     f.p->start.coulomb_n_m, f.p->start.viscous_n_m_s_per_rad};
  for (std::size_t i = 0; i < kParameters; ++i) {
    ClearanceParameter q;
    q.name = kNames[i];
    q.value = values[i];
    q.start = starts[i];
    const auto it = std::find(f.active.begin(), f.active.end(), i);
    q.free = it != f.active.end() || (i == kD && f.per_run_damping);
    q.std_error = i == kD && f.per_run_damping ? d_sigma : std::numeric_limits<double>::quiet_NaN();
    if (it != f.active.end() && cov.ok) {
      const auto c = static_cast<Eigen::Index>(it - f.active.begin());
      const double sd = std::sqrt(cov.cov(c, c));
      // Log variables: σ of the log is the relative σ; c and b are linear: σ / value.
      q.std_error = i == kC || i == kB ? (f.theta[i] > 0.0 ? sd / f.theta[i] : std::numeric_limits<double>::quiet_NaN()) : sd;
      const double tol = 1e-6 * (f.upper[i] - f.lower[i]);
      // c, b ≥ 0 is the law's own domain: a fit at 0 is a finding, not a search cut short.
      q.at_bound = (f.theta[i] <= f.lower[i] + tol && i != kC && i != kB) || f.theta[i] >= f.upper[i] - tol;
    }
    q.identifiable = std::isfinite(q.std_error) && q.std_error < 0.1;
    out.parameters.push_back(q);
  }
  for (std::size_t i = 0; i < n; ++i) {
    out.run_ids.push_back(f.p->runs[i].id);
    out.start_fraction.push_back(v.start[i]);
    const auto c = static_cast<Eigen::Index>(p + i);
    out.start_fraction_std.push_back(cov.ok ? std::sqrt(cov.cov(c, c)) : std::numeric_limits<double>::quiet_NaN());
    out.run_damping.push_back(f.per_run_damping ? std::exp(v.log_damping[i]) : m.damping);
  }
}

// The friction law's structural uncertainty: the bearing's viscous term trades against the
// Coulomb torque (and an unmodelled drag of the link on the ground against both). The optimum
// refitted with b held at 0 — its shift of each variable is a systematic 1σ added in quadrature.
Theta structural_shift(Fit& f, const Runs& v) {
  Theta shift{};
  if (!is_active(f, kB)) return shift;
  Fit g = f;
  std::erase(g.active, kB);
  g.theta[kB] = 0.0;
  Runs w = v;
  try {
    (void)refine(g, w);
  } catch (const std::exception&) {
    return shift;
  }
  f.simulations = g.simulations;
  for (std::size_t i = 0; i < kShared; ++i) shift[i] = i == kB ? 0.0 : g.theta[i] - f.theta[i];
  return shift;
}

ClearanceRunsFitResult tabulate(Fit& f, const Refined& fit, const Runs& v) {
  ClearanceRunsFitResult out;
  out.iterations = fit.iterations;
  out.converged = fit.converged;
  out.termination = fit.termination;
  out.sensor_low_pass_hz = bandwidth(f, f.theta);
  Covariance cov = covariance(f, fit);
  // The check: the optimum through CVODE at the fit's tolerances (rtol 1e-7). Its residual moves
  // the optimum by the Gauss–Newton step −(JᵀJ)⁻¹Jᵀr_CVODE: the inner loop's integrator error,
  // a systematic 1σ added in quadrature, as is the friction law's structural shift.
  std::vector<Job> jobs;
  for (std::size_t i = 0; i < f.runs(); ++i) jobs.push_back(job(f, f.theta, v, i, v.start[i]));
  const auto checked = residuals(f, jobs, false);
  double check_ssr = 0.0;
  for (const auto& r : checked) check_ssr += ssr_of(r);
  const Theta shift = structural_shift(f, v);
  if (cov.ok && std::isfinite(check_ssr)) {
    const Eigen::VectorXd step = (fit.J.transpose() * fit.J).ldlt().solve(-(fit.J.transpose() * stack(checked, f.samples)));
    for (std::size_t c = 0; c < f.active.size(); ++c) {
      const auto d = static_cast<Eigen::Index>(c);
      cov.cov(d, d) += shift[f.active[c]] * shift[f.active[c]] + step(d) * step(d);
    }
  }
  describe(f, v, cov, out);
  double total = 0.0;
  for (std::size_t i = 0; i < f.runs(); ++i) {
    const double e = ssr_of(fit.residual[i]);
    out.run_rms_error_deg_s.push_back(std::sqrt(e / static_cast<double>(f.samples)));
    total += e;
  }
  const auto count = static_cast<double>(f.samples * f.runs());
  out.rms_error_deg_s = std::sqrt(total / count);
  out.check_rms_error_deg_s = std::sqrt(check_ssr / count);
  if (f.p->check_exponent && out.model.exponent == 1.0) exponent_score(f, fit, v, cov, out);
  out.simulations = f.simulations;
  return out;
}

}  // namespace

double spread_upper_bound(const std::vector<double>& log_values, double confidence) {
  require_in_open("confidence", confidence, 0.0, 1.0);
  const auto n = log_values.size();
  if (n < 3) return 0.0;
  double mean = 0.0;
  for (const double v : log_values) mean += v / static_cast<double>(n);
  double ss = 0.0;
  for (const double v : log_values) ss += (v - mean) * (v - mean);
  // σ ≤ √(SS / χ²_{1−confidence, n−1}): the one-sided bound on a normal sample's σ (Montgomery §7.4).
  return std::sqrt(ss / distributions::chi_squared_quantile(static_cast<double>(n - 1), 1.0 - confidence));
}

ClearanceModelSigma ClearanceRunsFitResult::sigma() const {
  ClearanceModelSigma s;
  for (const auto& q : parameters) {
    if (q.name == "play") s.play_rel_sigma = q.std_error;
    if (q.name == "stiffness") s.stiffness_rel_sigma = q.std_error;
    if (q.name == "coulomb") s.coulomb_rel_sigma = q.std_error;
  }
  std::vector<double> log_damping;
  for (const double d : run_damping) {
    if (d > 0.0) log_damping.push_back(std::log(d));
  }
  s.damping_spread = spread_upper_bound(log_damping);
  return s;
}

ClearanceRunsFitResult fit_clearance_runs(const ClearanceRunsFitProblem& problem) {
  Runs v;
  Fit f = plan(problem, v);
  // Continuation in the window (chaotic rebounds make the full record's error landscape rough):
  // the scans and a first refinement on the move's first 0.25 s, then 0.6 s, then the whole.
  const auto window = [&f](double after_move_s) {
    const auto k = f.move_sample + static_cast<std::size_t>(std::llround(after_move_s / f.sample_time_s));
    f.samples = std::clamp<std::size_t>(k, std::min<std::size_t>(10, f.full_samples), f.full_samples);
  };
  window(0.25);
  // A first refinement from each of the scan's best points; the lowest error goes on.
  Refined fit;
  fit.ssr = std::numeric_limits<double>::infinity();
  const Fit base = f;
  for (const ScanPoint& start : scan_grid(f, v)) {
    Fit g = base;
    g.simulations = f.simulations;
    Runs w;
    scan_friction(g, w, start);
    Refined r = refine(g, w);
    f.simulations = g.simulations;
    if (r.ssr < fit.ssr) {
      const int simulations = f.simulations;
      f = g;
      f.simulations = simulations;
      v = w;
      fit = std::move(r);
    }
  }
  window(0.6);
  hop_runs(f, fit, v);
  fit = refine(f, v);
  window(1e9);
  hop_runs(f, fit, v);
  fit = refine(f, v);
  for (int hop = 0; hop < 2 && hop_runs(f, fit, v); ++hop) fit = refine(f, v);
  return tabulate(f, fit, v);
}

}  // namespace clearshape::study
