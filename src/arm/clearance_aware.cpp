#include "clearshape/arm/clearance_aware.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <thread>

#include <fmt/format.h>
#include <nlopt.h>

#include "clearshape/arm/modes.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::arm {

void ArmClearanceAwareOptions::validate(int dof) const {
  if (slots < 2 || slots > 32) throw_invalid("slots", slots, "2 … 32");
  require_in_closed("grid_s", grid_s, 0.0, 1.0, "0: a quarter period of the end pose's lowest mode");
  if (max_evaluations < 10) throw_invalid("max_evaluations", max_evaluations, ">= 10");
  if (threads < 1 || threads > 64) throw_invalid("threads", threads, "1 … 64");
  for (std::size_t s = 0; s < start_places.size(); ++s) {
    if (start_places[s].size() != dof) {
      throw_invalid(fmt::format("start_places[{}] size", s), static_cast<double>(start_places[s].size()),
                    fmt::format("{} (one per joint)", dof));
    }
    for (Eigen::Index i = 0; i < start_places[s].size(); ++i) {
      require_in_closed(fmt::format("start_places[{}][{}]", s, i), start_places[s](i), -1.0, 1.0);
    }
  }
}

namespace {

std::vector<Eigen::VectorXd> default_start_places(int dof) {
  std::vector<Eigen::VectorXd> places;
  for (const double f : {-1.0, 0.0, 1.0}) places.push_back(Eigen::VectorXd::Constant(dof, f));
  for (const double sign : {1.0, -1.0}) {  // the mixed corners: alternate joints at −1 and +1
    Eigen::VectorXd v(dof);
    for (int i = 0; i < dof; ++i) v(i) = (i % 2 == 0 ? -sign : sign);
    places.push_back(v);
  }
  return places;
}

struct Problem {
  const ArmModel* arm = nullptr;
  const PointToPoint* move = nullptr;
  const ArmClearanceAwareOptions* options = nullptr;
  std::vector<Eigen::VectorXd> starts;
  std::vector<double> slot_times_s;
  std::vector<double> unshaped;
  std::vector<double> last;
  int evaluations = 0;
  std::exception_ptr error;
};

shaping::Shaper shaper_of(const std::vector<double>& slot_times_s, const double* x) {
  return shaping::positive_shaper_on_slots("arm-clearance-aware", slot_times_s,
                                           std::span<const double>(x, slot_times_s.size()));
}

// The tool residual from every start place with `shaper` on every joint; thread j takes start
// places j, j + T, … (a fixed assignment).
std::vector<double> residuals(const Problem& p, const shaping::Shaper& shaper) {
  const std::vector<shaping::Shaper> shapers(static_cast<std::size_t>(p.arm->dof()), shaper);
  std::vector<double> out(p.starts.size(), 0.0);
  const auto threads = static_cast<std::size_t>(std::min<int>(p.options->threads, static_cast<int>(p.starts.size())));
  std::vector<std::exception_ptr> errors(threads);
  const auto work = [&](std::size_t j) {
    try {
      for (std::size_t s = j; s < p.starts.size(); s += threads) {
        MovePlayOptions o = p.options->play;
        o.start_play_fraction = p.starts[s];
        try {
          out[s] = play_move_with(*p.arm, *p.move, shapers, o).residual_m;
        } catch (const RuntimeError&) {  // CVODE could not finish this trial: a point to reject
          out[s] = std::numeric_limits<double>::infinity();
        }
      }
    } catch (...) {
      errors[j] = std::current_exception();
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t j = 1; j < threads; ++j) pool.emplace_back(work, j);
  work(0);
  for (auto& t : pool) t.join();
  for (const auto& e : errors) {
    if (e) std::rethrow_exception(e);
  }
  return out;
}

// J = max r + 0.1 · mean r, r_s = residual_s / max(unshaped_s, ¼ max unshaped) (header).
double objective(const std::vector<double>& shaped, const std::vector<double>& unshaped) {
  const double floor = 0.25 * std::max(1e-15, *std::max_element(unshaped.begin(), unshaped.end()));
  double worst = 0.0, mean = 0.0;
  for (std::size_t s = 0; s < shaped.size(); ++s) {
    const double r = shaped[s] / std::max(unshaped[s], floor);
    worst = std::max(worst, r);
    mean += r / static_cast<double>(shaped.size());
  }
  return worst + 0.1 * mean;
}

double nlopt_objective(unsigned /*n*/, const double* x, double* /*grad*/, void* data) {
  auto& p = *static_cast<Problem*>(data);
  try {
    ++p.evaluations;
    p.last = residuals(p, shaper_of(p.slot_times_s, x));
    return objective(p.last, p.unshaped);
  } catch (...) {
    p.error = std::current_exception();
    return HUGE_VAL;
  }
}

// A quarter period of the end pose's lowest linearised mode (arm/modes.hpp).
double default_grid_s(const ArmModel& arm, const Eigen::VectorXd& end_pose) {
  const ArmModes modes = joint_modes(arm, end_pose);
  double lowest_hz = std::numeric_limits<double>::infinity();
  for (int i = 0; i < arm.dof(); ++i) lowest_hz = std::min(lowest_hz, modes.joint_mode(i).natural_frequency_hz());
  return 0.25 / lowest_hz;
}

}  // namespace

ArmClearanceAwareResult design_clearance_aware_move(const ArmModel& arm, const PointToPoint& move,
                                                    const ArmClearanceAwareOptions& options) {
  options.validate(arm.dof());
  Problem p;
  p.arm = &arm;
  p.move = &move;
  p.options = &options;
  p.starts = options.start_places.empty() ? default_start_places(arm.dof()) : options.start_places;
  const double grid_s = options.grid_s > 0.0 ? options.grid_s : default_grid_s(arm, move.to_rad);
  for (int k = 0; k < options.slots; ++k) p.slot_times_s.push_back(k * grid_s);
  p.unshaped = residuals(p, shaping::Shaper("unshaped", {{0.0, 1.0}}));
  for (std::size_t s = 0; s < p.unshaped.size(); ++s) {
    if (!std::isfinite(p.unshaped[s])) {
      throw RuntimeError(fmt::format("arm clearance-aware design: the unshaped move from start place {} cannot be "
                                     "simulated", s));
    }
  }

  std::vector<double> x(static_cast<std::size_t>(options.slots), 1.0 / options.slots);  // the staircase
  nlopt_opt opt = nlopt_create(NLOPT_LN_SBPLX, static_cast<unsigned>(options.slots));
  const std::vector<double> lower(x.size(), 0.0), upper(x.size(), 1.0);
  nlopt_set_lower_bounds(opt, lower.data());
  nlopt_set_upper_bounds(opt, upper.data());
  nlopt_set_min_objective(opt, nlopt_objective, &p);
  nlopt_set_maxeval(opt, options.max_evaluations);
  double best = 0.0;
  const nlopt_result status = nlopt_optimize(opt, x.data(), &best);
  nlopt_destroy(opt);
  if (p.error) std::rethrow_exception(p.error);
  if (status < 0 && status != NLOPT_ROUNDOFF_LIMITED) {
    throw RuntimeError(fmt::format("arm clearance-aware design: NLopt failed ({})", static_cast<int>(status)));
  }
  ArmClearanceAwareResult out;
  out.shaper = shaper_of(p.slot_times_s, x.data());
  out.start_places = p.starts;
  out.unshaped_residual_m = p.unshaped;
  out.shaped_residual_m = residuals(p, out.shaper);
  for (std::size_t s = 0; s < p.starts.size(); ++s) {
    const double r = p.unshaped[s] > 0.0 ? out.shaped_residual_m[s] / p.unshaped[s] : 0.0;
    out.worst_ratio = std::max(out.worst_ratio, r);
    out.worse_than_unshaped = out.worse_than_unshaped || out.shaped_residual_m[s] > p.unshaped[s];
  }
  out.evaluations = p.evaluations;
  return out;
}

BenchmarkDesign clearance_aware_benchmark(const ArmModel& arm, std::span<const PointToPoint> moves,
                                          const ArmClearanceAwareOptions& options, const BenchmarkDesign& unshaped) {
  BenchmarkDesign out;
  out.name = "clearance-aware";
  for (const PointToPoint& m : moves) {
    const ArmClearanceAwareResult d = design_clearance_aware_move(arm, m, options);
    const std::vector<shaping::Shaper> shapers(static_cast<std::size_t>(arm.dof()), d.shaper);
    out.moves.push_back(play_move_with(arm, m, shapers, options.play));
    out.total_residual_m += out.moves.back().residual_m;
  }
  out.improvement = unshaped.total_residual_m > 0.0 ? 1.0 - out.total_residual_m / unshaped.total_residual_m : 0.0;
  return out;
}

}  // namespace clearshape::arm
