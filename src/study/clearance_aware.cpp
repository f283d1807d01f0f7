#include "clearshape/study/clearance_aware.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <numbers>
#include <optional>
#include <string>
#include <thread>

#include <fmt/format.h>
#include <nlopt.h>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "clearshape/shaping/apply.hpp"

namespace clearshape::study {

std::vector<double> default_start_fractions() { return {-1.0, -0.5, 0.0, 0.5, 1.0}; }

std::vector<UncertaintyPoint> uncertainty_set(double play_rel_sigma, double stiffness_rel_sigma,
                                              double coulomb_rel_sigma, const std::vector<double>& start_fractions,
                                              double damping_spread) {
  for (const auto& [name, v] : {std::pair{"play_rel_sigma", play_rel_sigma}, {"stiffness_rel_sigma", stiffness_rel_sigma},
                                {"coulomb_rel_sigma", coulomb_rel_sigma}}) {
    require_in_closed(name, v, 0.0, 0.9, "A relative 1σ of 90 % or more leaves no model to design on");
  }
  require_in_closed("damping_spread", damping_spread, 0.0, 2.0, "The 1σ of ln D over runs");
  std::vector<UncertaintyPoint> points;
  const auto add = [&](double sign) {
    for (const double f : start_fractions) {
      points.push_back({1.0 + sign * play_rel_sigma, 1.0 + sign * stiffness_rel_sigma, f, 1.0 - sign * coulomb_rel_sigma});
    }
  };
  add(0.0);
  if (play_rel_sigma > 0.0 || stiffness_rel_sigma > 0.0 || coulomb_rel_sigma > 0.0) {
    add(-1.0);
    add(1.0);
  }
  if (damping_spread > 0.0) {
    for (const double sign : {-1.0, 1.0}) {
      for (const double f : start_fractions) points.push_back({1.0, 1.0, f, 1.0, std::exp(sign * damping_spread)});
    }
  }
  return points;
}

std::vector<UncertaintyPoint> default_uncertainty() { return uncertainty_set(); }

std::vector<UncertaintyPoint> design_uncertainty(const ClearanceModelSigma& sigma) {
  const auto cap = [](double v, double hi) { return std::isfinite(v) ? std::clamp(v, 0.0, hi) : hi; };
  double sp = cap(sigma.play_rel_sigma, 0.5), sk = cap(sigma.stiffness_rel_sigma, 0.5), sc = cap(sigma.coulomb_rel_sigma, 0.5);
  if (std::max({sp, sk, sc}) < 0.02) sp = sk = sc = 0.0;
  const double sd = std::isfinite(sigma.damping_spread) ? std::clamp(sigma.damping_spread, 0.0, 1.0) : 0.0;
  return uncertainty_set(sp, sk, sc, default_start_fractions(), sd);
}

void ClearanceAwareRequest::validate() const {
  if (moves.empty() && profiles.empty()) throw InvalidArgument("moves: give at least one step amplitude");
  for (const auto& p : profiles) {
    if (p.command.values.empty()) throw InvalidArgument("profiles." + p.name + ": an empty command");
    if (std::abs(p.command.sample_time_s - sample_time_s) > 1e-12 * sample_time_s) {
      throw_invalid("profiles." + p.name + ".sample_time_s", p.command.sample_time_s, "the request's sample_time_s");
    }
    require_in_closed("profiles." + p.name + ".motion_end_s", p.motion_end_s, 0.0,
                      static_cast<double>(p.command.values.size()) * sample_time_s);
    require_in_closed("profiles." + p.name + ".last_move_start_s", p.last_move_start_s, 0.0, p.motion_end_s);
  }
  for (const double m : moves) {
    require_finite("moves", m);
    if (m == 0.0) throw InvalidArgument("moves: a step amplitude of 0 is no move; give non-zero amplitudes");
  }
  if (uncertainty.empty()) throw InvalidArgument("uncertainty: give at least one point");
  for (const auto& u : uncertainty) {
    require_in_closed("uncertainty.play_factor", u.play_factor, 1e-3, 10.0);
    require_in_closed("uncertainty.stiffness_factor", u.stiffness_factor, 1e-3, 100.0);
    require_in_closed("uncertainty.initial_play_fraction", u.initial_play_fraction, -1.0, 1.0);
    require_in_closed("uncertainty.coulomb_factor", u.coulomb_factor, 0.0, 10.0);
    require_in_closed("uncertainty.damping_factor", u.damping_factor, 1e-3, 10.0);
  }
  require_in_closed("max_duration_s", max_duration_s, 1e-3, 5.0, "Use the duration of the linear shaper it replaces");
  require_in_closed("grid_s", grid_s, 1e-4, 1.0);
  require_in_closed("rise_s", rise_s, 0.0, 1.0);
  require_in_closed("move_start_s", move_start_s, 0.0, 10.0);
  require_in_closed("settle_s", settle_s, 0.1, 30.0);
  require_in_closed("sample_time_s", sample_time_s, 1e-5, 0.01);
  if (max_evaluations < 10) throw_invalid("max_evaluations", max_evaluations, ">= 10");
  if (threads < 0) throw_invalid("threads", threads, ">= 0 (0: the hardware's threads)");
  if (!(model.play_rad > 0.0)) throw InvalidArgument("model.play_rad: the model has no play; a linear shaper suffices");
}

namespace {

// The step command: a ramp over rise_s starting at move_start_s, on the sample grid.
UniformSeries step_command(const ClearanceAwareRequest& r, double move, double duration_s) {
  const auto n = static_cast<std::size_t>(std::floor(duration_s / r.sample_time_s + 1e-9)) + 1;
  UniformSeries s{0.0, r.sample_time_s, std::vector<double>(n, 0.0)};
  for (std::size_t k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * r.sample_time_s - r.move_start_s;
    s.values[k] = t <= 0.0 ? 0.0 : r.rise_s <= 0.0 ? move : move * std::min(1.0, t / r.rise_s);
  }
  return s;
}

// The command held at its last value out to `duration_s`.
UniformSeries extended(const UniformSeries& c, double duration_s) {
  UniformSeries out = c;
  const std::size_t n = static_cast<std::size_t>(std::floor(duration_s / c.sample_time_s + 1e-9)) + 1;
  if (out.values.size() < n) out.values.resize(n, c.values.back());
  return out;
}

struct Problem {
  const ClearanceAwareRequest* request = nullptr;
  std::vector<DesignMove> moves;
  std::vector<ClearanceModel> models;   // one per uncertainty point
  std::vector<double> slot_times_s;     // impulse grid
  std::vector<double> unshaped_md;      // per case
  std::vector<double> last_md;          // per case, of the last evaluation
  int evaluations = 0;
  int threads = 1;
  std::exception_ptr error;
};

shaping::Shaper shaper_of(const std::vector<double>& slot_times_s, const double* x) {
  return shaping::positive_shaper_on_slots("clearance-aware", slot_times_s, std::span<const double>(x, slot_times_s.size()));
}

// The simulated length of a case: the move, the longest shaper and the settling time.
double case_duration_s(const ClearanceAwareRequest& r, const DesignMove& move) {
  return std::max(static_cast<double>(move.command.values.size() - 1) * r.sample_time_s, move.motion_end_s) +
         r.max_duration_s + r.settle_s;
}

// Eq. 5.1 on a case's simulated link angle, from the start of the (last) move as the study does
// (so a late settle counts).
double case_md_of(const ClearanceAwareRequest& r, const DesignMove& move, const ModelResponse& response) {
  metrics::MeanDeviationOptions options;
  options.search_from_s = r.profiles.empty() ? r.move_start_s : move.last_move_start_s;
  return metrics::mean_deviation(UniformSeries{0.0, response.sample_time_s, response.link_angle_deg}, options)
      .mean_deviation;
}

// MDs of cases [c0, c1) (case c: move c / points, uncertainty point c % points) into md,
// simulated together (simulate_drive_commands): each MD is clearance_aware_case_md's to the bit.
void case_mds_together(const Problem& p, const shaping::Shaper& shaper, std::size_t c0, std::size_t c1,
                       std::vector<double>& md) {
  const ClearanceAwareRequest& r = *p.request;
  const std::size_t n_points = r.uncertainty.size();
  std::vector<UniformSeries> drives;
  std::vector<double> durations;
  for (std::size_t c = c0; c < c1; ++c) {
    const DesignMove& move = p.moves[c / n_points];
    durations.push_back(case_duration_s(r, move));
    const UniformSeries command = shaping::shape_offline(shaper, extended(move.command, durations.back()), false);
    drives.push_back(drive_command_of(p.models[c % n_points], command, durations.back()));
  }
  std::vector<DriveCommandJob> jobs;
  for (std::size_t c = c0; c < c1; ++c) {
    jobs.push_back({&p.models[c % n_points], &drives[c - c0], durations[c - c0], r.uncertainty[c % n_points].initial_play_fraction});
  }
  const std::vector<DriveCommandOutcome> outcomes = simulate_drive_commands(jobs);
  for (std::size_t c = c0; c < c1; ++c) {
    if (outcomes[c - c0].error) std::rethrow_exception(outcomes[c - c0].error);
    md[c] = case_md_of(r, p.moves[c / n_points], outcomes[c - c0].response);
  }
}

// MD of every case for `shaper`, in parallel: thread j takes the pairs of cases (2q, 2q + 1) for
// q = j, j + T, j + 2T, …, each pair simulated together (case_mds_together).
std::vector<double> case_mds(const Problem& p, const shaping::Shaper& shaper) {
  const ClearanceAwareRequest& r = *p.request;
  const std::size_t n_cases = p.moves.size() * r.uncertainty.size();
  std::vector<double> md(n_cases, 0.0);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(p.threads));
  const auto threads = static_cast<std::size_t>(p.threads);
  const auto work = [&](std::size_t j) {
    try {
      for (std::size_t c = 2 * j; c < n_cases; c += 2 * threads) case_mds_together(p, shaper, c, std::min(c + 2, n_cases), md);
    } catch (...) {
      errors[j] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (int j = 1; j < p.threads; ++j) pool.emplace_back(work, static_cast<std::size_t>(j));
  work(0);
  for (auto& t : pool) t.join();
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  return md;
}

// Each case relative to itself unshaped (header); a case whose unshaped MD is below a quarter of
// the largest is judged against that quarter instead, so a move the unshaped command already
// leaves nearly still (e.g. a slow low-jerk ramp) cannot trade the others' residual for its own.
std::vector<double> ratios_of(const std::vector<double>& md, const std::vector<double>& unshaped) {
  const double floor = 0.25 * std::max(1e-12, *std::max_element(unshaped.begin(), unshaped.end()));
  std::vector<double> r(md.size());
  for (std::size_t c = 0; c < md.size(); ++c) r[c] = md[c] / std::max(unshaped[c], floor);
  return r;
}

// The reported objective (header): J = max r + 0.1·mean r.
double objective_of(const std::vector<double>& ratio) {
  double worst = 0.0, mean = 0.0;
  for (const double v : ratio) {
    worst = std::max(worst, v);
    mean += v;
  }
  return worst + 0.1 * mean / static_cast<double>(ratio.size());
}

// What the search minimizes: the max replaced by the power mean M_8 = (mean r⁸)^(1/8), which
// lies within a factor N^(1/8) of the max and is smooth where the max has kinks (a derivative-free
// search stalls on the max's kinks); plus the same 0.1·mean.
double search_objective_of(const std::vector<double>& ratio) {
  double power = 0.0, mean = 0.0;
  for (const double v : ratio) {
    power += std::pow(v, 8.0);
    mean += v;
  }
  const auto n = static_cast<double>(ratio.size());
  return std::pow(power / n, 1.0 / 8.0) + 0.1 * mean / n;
}

double nlopt_objective(unsigned n, const double* x, double* /*grad*/, void* data) {
  auto& p = *static_cast<Problem*>(data);
  try {
    ++p.evaluations;
    p.last_md = case_mds(p, shaper_of(p.slot_times_s, x));
    (void)n;
    return search_objective_of(ratios_of(p.last_md, p.unshaped_md));
  } catch (...) {
    p.error = std::current_exception();
    return HUGE_VAL;
  }
}

}  // namespace

ClearanceModel varied_model(const ClearanceModel& m, const UncertaintyPoint& u) {
  ClearanceModel v = m;
  v.play_rad *= u.play_factor;
  v.stiffness *= u.stiffness_factor;
  v.coulomb_n_m *= u.coulomb_factor;
  v.damping *= u.damping_factor;
  return v;
}

std::optional<DesignMove> design_move(const std::string& name, const signal::Signal& signal, double sample_rate_hz,
                                      double record_s, double update_period_s) {
  const UniformSeries full = signal::sample(signal, sample_rate_hz, record_s);
  std::size_t first = 0, last = 0;  // the first and last sample that differ from their predecessor
  for (std::size_t k = 1; k < full.values.size(); ++k) {
    if (full.values[k] != full.values[k - 1]) {
      if (first == 0) first = k;
      last = k;
    }
  }
  if (first == 0) return std::nullopt;
  std::size_t begin = first - 1 - std::min(first - 1, static_cast<std::size_t>(std::llround(0.05 * sample_rate_hz)));
  if (update_period_s > 0.0) {
    // Cut whole update periods only, so the drive's update grid meets the move as it does in the
    // full record (the pulse path reads the command at its updates): the shortest run of periods
    // that is a whole number of samples (30 Hz at 1 kHz: three, 100 samples).
    std::size_t block = 0;
    for (int m = 1; m <= 1000 && block == 0; ++m) {
      const double samples = m * update_period_s * sample_rate_hz;
      if (std::abs(samples - std::round(samples)) < 1e-6) block = static_cast<std::size_t>(std::llround(samples));
    }
    begin = block == 0 ? 0 : (begin / block) * block;
  }
  DesignMove m;
  m.name = name;
  m.command = UniformSeries{0.0, full.sample_time_s,
                            std::vector<double>(full.values.begin() + static_cast<std::ptrdiff_t>(begin),
                                                full.values.begin() + static_cast<std::ptrdiff_t>(last) + 1)};
  m.motion_end_s = static_cast<double>(last - begin) * full.sample_time_s;
  // Eq. 5.1 searches from the start of the last move, as the study does (InputSpec::last_move_start_s):
  // the first sample of the final run of changing samples.
  std::size_t run = last;
  while (run > first && full.values[run - 1] != full.values[run - 2]) --run;
  m.last_move_start_s = static_cast<double>(run - 1 - begin) * full.sample_time_s;
  return m;
}

std::vector<DesignMove> design_moves(const ClearanceAwareRequest& r) {
  if (!r.profiles.empty()) return r.profiles;
  std::vector<DesignMove> moves;
  for (const double m : r.moves) {
    moves.push_back(
        // One sample past the end of the ramp, so the command holds the move itself (a step at
        // move_start_s would otherwise end on its last zero).
        {fmt::format("{:g}", m), step_command(r, m, r.move_start_s + r.rise_s + r.sample_time_s), r.move_start_s + r.rise_s,
         r.move_start_s});
  }
  return moves;
}

double clearance_aware_case_md(const ClearanceAwareRequest& r, const ClearanceModel& model, const DesignMove& move,
                               double initial_play_fraction, const shaping::Shaper& shaper) {
  const double duration_s = case_duration_s(r, move);
  const UniformSeries command = shaping::shape_offline(shaper, extended(move.command, duration_s), false);
  return case_md_of(r, move, simulate_command(model, command, duration_s, initial_play_fraction, true));
}

namespace {

// The ZV pair (Singer & Seering 1990) at the flank's linear mode ω = √(K/J), its second impulse
// on the nearest grid slot: a start near the linear answer for the search.
std::vector<double> zv_start(const ClearanceModel& m, const std::vector<double>& slot_times_s) {
  std::vector<double> x(slot_times_s.size(), 0.0);
  const double half_period_s = std::numbers::pi / std::sqrt(m.stiffness / m.link_inertia_kg_m2);
  const double grid_s = slot_times_s.size() > 1 ? slot_times_s[1] : 1.0;
  const auto k = static_cast<std::size_t>(std::clamp(std::round(half_period_s / grid_s), 1.0,
                                                     static_cast<double>(slot_times_s.size() - 1)));
  x[0] = 0.5;
  x[k] = 0.5;
  return x;
}

// One SBPLX search from x (header); returns its objective and leaves the optimum in x.
double search(Problem& p, std::vector<double>& x, int budget, std::string& termination) {
  const auto n = static_cast<unsigned>(x.size());
  std::unique_ptr<nlopt_opt_s, decltype(&nlopt_destroy)> opt(nlopt_create(NLOPT_LN_SBPLX, n), nlopt_destroy);
  if (!opt) throw RuntimeError("clearance-aware design: NLopt could not create the optimizer");
  const std::vector<double> lo(n, 0.0), hi(n, 1.0), step(n, 0.25);
  nlopt_set_lower_bounds(opt.get(), lo.data());
  nlopt_set_upper_bounds(opt.get(), hi.data());
  nlopt_set_initial_step(opt.get(), step.data());
  nlopt_set_min_objective(opt.get(), nlopt_objective, &p);
  nlopt_set_maxeval(opt.get(), budget);
  nlopt_set_xtol_rel(opt.get(), 1e-3);
  nlopt_set_ftol_abs(opt.get(), 1e-6);
  double f = HUGE_VAL;
  const nlopt_result status = nlopt_optimize(opt.get(), x.data(), &f);
  if (p.error) std::rethrow_exception(p.error);
  if (status < 0 && status != NLOPT_ROUNDOFF_LIMITED) {
    throw RuntimeError(fmt::format("clearance-aware design: NLopt failed: {}", nlopt_result_to_string(status)));
  }
  termination = nlopt_result_to_string(status);
  return f;
}

}  // namespace

ClearanceAwareResult design_clearance_aware(const ClearanceAwareRequest& request) {
  request.validate();
  Problem p;
  p.request = &request;
  p.moves = design_moves(request);
  for (const auto& u : request.uncertainty) p.models.push_back(varied_model(request.model, u));
  const auto slots = static_cast<std::size_t>(std::floor(request.max_duration_s / request.grid_s + 1e-9)) + 1;
  for (std::size_t k = 0; k < slots; ++k) p.slot_times_s.push_back(static_cast<double>(k) * request.grid_s);
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t n_points = request.uncertainty.size();
  const std::size_t n_cases = p.moves.size() * n_points;
  p.threads = std::clamp(request.threads > 0 ? request.threads : hardware, 1, static_cast<int>(n_cases));

  ClearanceAwareResult result;
  p.unshaped_md = case_mds(p, shaping::Shaper("none", {{0.0, 1.0}}));

  // Three starts (header): the unshaped step, the uniform staircase, the ZV pair on the grid.
  std::vector<double> best_x(slots, 0.0);
  if (!best_x.empty()) best_x[0] = 1.0;  // never empty (slots ≥ 1); GCC 12 -Wnull-dereference cannot tell
  if (slots == 1) {
    result.termination = "one impulse slot (the bound is shorter than the grid)";
  } else {
    std::vector<std::vector<double>> starts{best_x, std::vector<double>(slots, 0.5), zv_start(request.model, p.slot_times_s)};
    // A coarse scout first (header): the first four slots on a grid of relative amplitudes
    // {0, ¼, ½, ¾, 1} against slot 0 — 125 designs, deterministic, when the budget allows twice
    // that; then each start for a sixth of the budget; the best one continues with the rest.
    double best = HUGE_VAL;
    if (slots >= 4 && request.max_evaluations >= 250) {
      for (int code = 0; code < 125; ++code) {
        std::vector<double> x(slots, 0.0);
        x[0] = 1.0;
        x[1] = 0.25 * (code % 5);
        x[2] = 0.25 * ((code / 5) % 5);
        x[3] = 0.25 * (code / 25);
        const double f = nlopt_objective(static_cast<unsigned>(slots), x.data(), nullptr, &p);
        if (p.error) std::rethrow_exception(p.error);
        if (f < best) {
          best = f;
          best_x = x;
          result.termination = "grid scout";
        }
      }
      starts.push_back(best_x);
    }
    const int scout = std::max(2, request.max_evaluations / 6);
    for (auto& x : starts) {
      const int budget = std::min(scout, request.max_evaluations - p.evaluations);
      if (budget < 2) break;
      std::string termination;
      const double f = search(p, x, budget, termination);
      if (f < best) {
        best = f;
        best_x = x;
        result.termination = termination;
      }
    }
    const int rest = request.max_evaluations - p.evaluations;
    if (rest >= 2) {
      std::vector<double> x = best_x;
      std::string termination;
      if (search(p, x, rest, termination) < best) {
        best_x = x;
        result.termination = termination;
      }
    }
  }
  result.shaper = shaper_of(p.slot_times_s, best_x.data());
  const std::vector<double> best_md = case_mds(p, result.shaper);  // the reported cases: re-simulated
  const std::vector<double> ratio = ratios_of(best_md, p.unshaped_md);
  result.objective = objective_of(ratio);
  result.evaluations = p.evaluations;
  for (std::size_t c = 0; c < n_cases; ++c) {
    const DesignMove& move = p.moves[c / n_points];
    const double final_value = move.command.values.back();
    result.cases.push_back({move.name, final_value, request.uncertainty[c % n_points], p.unshaped_md[c], best_md[c]});
    result.worst_md_deg = std::max(result.worst_md_deg, best_md[c]);
    result.worst_unshaped_md_deg = std::max(result.worst_unshaped_md_deg, p.unshaped_md[c]);
    result.worst_ratio = std::max(result.worst_ratio, ratio[c]);
  }
  result.worse_than_unshaped = result.worst_ratio > 1.0;
  return result;
}

}  // namespace clearshape::study
