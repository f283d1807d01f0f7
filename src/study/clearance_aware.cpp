#include "clearshape/study/clearance_aware.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <memory>
#include <thread>

#include <fmt/format.h>
#include <nlopt.h>

#include "clearshape/core/error.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "clearshape/shaping/apply.hpp"

namespace clearshape::study {

std::vector<UncertaintyPoint> default_uncertainty() {
  return {{1.0, 1.0, 0.0}, {0.8, 0.5, -1.0}, {1.2, 2.0, 1.0}};
}

void ClearanceAwareRequest::validate() const {
  if (moves.empty()) throw InvalidArgument("moves: give at least one step amplitude");
  for (const double m : moves) {
    require_finite("moves", m);
    if (m == 0.0) throw InvalidArgument("moves: a step amplitude of 0 is no move; give non-zero amplitudes");
  }
  if (uncertainty.empty()) throw InvalidArgument("uncertainty: give at least one point");
  for (const auto& u : uncertainty) {
    require_in_closed("uncertainty.play_factor", u.play_factor, 1e-3, 10.0);
    require_in_closed("uncertainty.stiffness_factor", u.stiffness_factor, 1e-3, 100.0);
    require_in_closed("uncertainty.initial_play_fraction", u.initial_play_fraction, -1.0, 1.0);
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

ClearanceModel varied(const ClearanceModel& m, const UncertaintyPoint& u) {
  ClearanceModel v = m;
  v.play_rad *= u.play_factor;
  v.stiffness *= u.stiffness_factor;
  return v;
}

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

double record_s(const ClearanceAwareRequest& r) { return r.move_start_s + r.max_duration_s + r.rise_s + r.settle_s; }

struct Problem {
  const ClearanceAwareRequest* request = nullptr;
  std::vector<ClearanceModel> models;   // one per uncertainty point
  std::vector<double> slot_times_s;     // impulse grid
  std::vector<double> last_md;          // per case, of the last evaluation
  int evaluations = 0;
  int threads = 1;
  std::exception_ptr error;
};

shaping::Shaper shaper_of(const std::vector<double>& slot_times_s, const double* x) {
  std::vector<shaping::Impulse> impulses;
  double sum = 0.0;
  for (std::size_t k = 0; k < slot_times_s.size(); ++k) sum += std::max(0.0, x[k]);
  for (std::size_t k = 0; k < slot_times_s.size(); ++k) {
    const double a = sum > 0.0 ? std::max(0.0, x[k]) / sum : (k == 0 ? 1.0 : 0.0);
    if (a > 0.0) impulses.push_back({slot_times_s[k], a});
  }
  if (impulses.empty()) impulses.push_back({0.0, 1.0});
  return shaping::Shaper("clearance-aware", std::move(impulses));
}

// MD of every case for `shaper`, in parallel: thread j takes cases j, j + T, j + 2T, …
std::vector<double> case_mds(const Problem& p, const shaping::Shaper& shaper) {
  const ClearanceAwareRequest& r = *p.request;
  const std::size_t n_points = r.uncertainty.size();
  const std::size_t n_cases = r.moves.size() * n_points;
  std::vector<double> md(n_cases, 0.0);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(p.threads));
  const auto work = [&](std::size_t j) {
    try {
      for (std::size_t c = j; c < n_cases; c += static_cast<std::size_t>(p.threads)) {
        const std::size_t m = c / n_points, u = c % n_points;
        md[c] = clearance_aware_case_md(r, p.models[u], r.moves[m], r.uncertainty[u].initial_play_fraction, shaper);
      }
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

double objective_of(const std::vector<double>& md) {
  double worst = 0.0, mean = 0.0;
  for (const double v : md) {
    worst = std::max(worst, v);
    mean += v;
  }
  return worst + 0.1 * mean / static_cast<double>(md.size());  // header: J = max + 0.1·mean
}

double nlopt_objective(unsigned n, const double* x, double* /*grad*/, void* data) {
  auto& p = *static_cast<Problem*>(data);
  try {
    ++p.evaluations;
    p.last_md = case_mds(p, shaper_of(p.slot_times_s, x));
    (void)n;
    return objective_of(p.last_md);
  } catch (...) {
    p.error = std::current_exception();
    return HUGE_VAL;
  }
}

}  // namespace

double clearance_aware_case_md(const ClearanceAwareRequest& r, const ClearanceModel& model, double move,
                               double initial_play_fraction, const shaping::Shaper& shaper) {
  const double duration_s = record_s(r);
  const UniformSeries command = shaping::shape_offline(shaper, step_command(r, move, duration_s), false);
  const ModelResponse response = simulate_command(model, command, duration_s, initial_play_fraction, true);
  metrics::MeanDeviationOptions options;
  options.search_from_s = r.move_start_s;
  return metrics::mean_deviation(UniformSeries{0.0, response.sample_time_s, response.link_angle_deg}, options)
      .mean_deviation;
}

ClearanceAwareResult design_clearance_aware(const ClearanceAwareRequest& request) {
  request.validate();
  Problem p;
  p.request = &request;
  for (const auto& u : request.uncertainty) p.models.push_back(varied(request.model, u));
  const auto slots = static_cast<std::size_t>(std::floor(request.max_duration_s / request.grid_s + 1e-9)) + 1;
  for (std::size_t k = 0; k < slots; ++k) p.slot_times_s.push_back(static_cast<double>(k) * request.grid_s);
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const std::size_t n_cases = request.moves.size() * request.uncertainty.size();
  p.threads = std::clamp(request.threads > 0 ? request.threads : hardware, 1, static_cast<int>(n_cases));

  ClearanceAwareResult result;
  const std::vector<double> unshaped = case_mds(p, shaping::Shaper("none", {{0.0, 1.0}}));

  // Two starts (header): the unshaped step and the uniform staircase.
  const unsigned n = static_cast<unsigned>(slots);
  std::vector<std::vector<double>> starts(2, std::vector<double>(slots, 0.0));
  starts[0][0] = 1.0;
  std::fill(starts[1].begin(), starts[1].end(), 0.5);
  double best = HUGE_VAL;
  std::vector<double> best_x;
  std::vector<double> best_md;
  int budget_left = request.max_evaluations;
  for (std::size_t s = 0; s < starts.size(); ++s) {
    std::vector<double> x = starts[s];
    if (n == 1) {  // one slot: the only positive shaper is the identity
      best_x = x;
      best_md = unshaped;
      best = objective_of(unshaped);
      result.termination = "one impulse slot (the bound is shorter than the grid)";
      break;
    }
    const int budget = s + 1 == starts.size() ? budget_left : request.max_evaluations / 2;
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
    const int before = p.evaluations;
    double f = HUGE_VAL;
    const nlopt_result status = nlopt_optimize(opt.get(), x.data(), &f);
    if (p.error) std::rethrow_exception(p.error);
    if (status < 0 && status != NLOPT_ROUNDOFF_LIMITED) {
      throw RuntimeError(fmt::format("clearance-aware design: NLopt failed: {}", nlopt_result_to_string(status)));
    }
    budget_left -= p.evaluations - before;
    if (f < best) {
      best = f;
      best_x = x;
      result.termination = nlopt_result_to_string(status);
    }
  }
  result.shaper = shaper_of(p.slot_times_s, best_x.data());
  best_md = case_mds(p, result.shaper);  // the reported cases: the result re-simulated
  result.objective = objective_of(best_md);
  result.evaluations = p.evaluations;
  for (std::size_t c = 0; c < n_cases; ++c) {
    const std::size_t m = c / request.uncertainty.size(), u = c % request.uncertainty.size();
    result.cases.push_back({request.moves[m], request.uncertainty[u], unshaped[c], best_md[c]});
    result.worst_md_deg = std::max(result.worst_md_deg, best_md[c]);
    result.worst_unshaped_md_deg = std::max(result.worst_unshaped_md_deg, unshaped[c]);
  }
  return result;
}

}  // namespace clearshape::study
