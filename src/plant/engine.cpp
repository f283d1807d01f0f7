#include "engine.hpp"

#include <cmath>
#include <limits>

#include <cvode/cvode.h>

#include "clearshape/core/error.hpp"
#include "planar_system.hpp"
#include "torsional_system.hpp"

namespace clearshape::plant::detail {

namespace {
constexpr int kTooManyTotalSteps = -1000;
constexpr int kRestartFailed = -1001;

bool reached(double t, double tout) noexcept {
  return tout - t <= 1e-12 * std::max(1.0, std::abs(tout));
}
}  // namespace

std::unique_ptr<JointSystem> make_system(const PlantModel& model, const SolverOptions& options) {
  model.validate();
  options.validate();
  if (std::holds_alternative<TorsionalClearance>(model.joint)) {
    return std::make_unique<TorsionalSystem>(model, options);
  }
  return std::make_unique<PlanarSystem>(model, options);
}

Engine::Engine(const PlantModel& model, const SolverOptions& options,
               std::vector<ContactEvent>* events, bool bounded_events)
    : system_(make_system(model, options)),
      solver_(*system_, options),
      log_(events, bounded_events),
      options_(options),
      found_(static_cast<std::size_t>(system_->root_count), 0) {}

void Engine::start(const InitialState& initial) {
  t_ = 0.0;
  log_.count = 0;
  restarts_ = 0;
  stops_ = 0;
  pending_flag_ = 0;
  root_pending_ = false;
  solver_.reset_stats();
  system_->initial_state(initial, system_->input.value(0.0), solver_.state(), log_);
  const int flag = restart();
  if (flag < 0) throw RuntimeError("plant: cannot start the integrator: " + failure(flag));
}

int Engine::restart() noexcept {
  ++restarts_;
  const int flag = solver_.restart(t_);
  return flag < 0 ? kRestartFailed : 0;
}

int Engine::set_held_input(double value) noexcept {
  if (system_->input.use_held && system_->input.held == value) return 0;
  system_->input.held = value;
  system_->on_input_jump(t_, solver_.state());
  ++stops_;
  return restart();
}

int Engine::run_to(double tout) noexcept {
  bool root_pending = false;  // a root return handled without restarting the integrator
  while (!reached(t_, tout)) {
    double tret = t_;
    const int flag = advance_after_root([&](double& r) { return solver_.advance(tout, r); },
                                        root_pending, tret);
    if (flag < 0) return flag;
    t_ = tret;
    if (flag == CV_SUCCESS) t_ = tout;  // tret == tout
    const int handled = handle_return(flag, root_pending);
    if (handled < 0) return handled;
  }
  if (system_->check_consistency(t_, solver_.state(), log_)) {
    if (restart() < 0) return kRestartFailed;
  }
  return 0;
}

// A root or stop return at t_: the mode update or the new input, and the restart they need.
int Engine::handle_return(int flag, bool& root_pending) noexcept {
  if (solver_.total_steps() > options_.max_total_steps) return kTooManyTotalSteps;
  if (flag == CV_ROOT_RETURN) {
    solver_.root_info(found_.data());
    if (system_->on_roots(t_, solver_.state(), found_.data(), log_)) {
      if (restart() < 0) return kRestartFailed;
    } else {
      root_pending = true;
    }
  } else if (flag == CV_TSTOP_RETURN) {
    if (stop_handler_) stop_handler_(stop_context_, t_, *system_);
    system_->on_input_jump(t_, solver_.state());
    ++stops_;
    if (restart() < 0) return kRestartFailed;
  }
  return 0;
}

template <class Advance>
int Engine::advance_after_root(Advance&& advance, bool& root_pending, double& tret) noexcept {
  int flag = advance(tret);
  if (flag == CV_ILL_INPUT && root_pending) {
    // CVODE refuses to continue when a root function stays exactly 0 just after the root
    // ("root found at and very near t"); y still holds the root state: restart from it.
    solver_.clear_message();
    if (restart() < 0) return kRestartFailed;
    flag = advance(tret);
  }
  root_pending = false;
  return flag;
}

int Engine::step_begin(double t_end, double& t_reached) noexcept {
  double tret = t_;
  const int flag = advance_after_root(
      [&](double& r) { return solver_.advance_one_step(t_end, r); }, root_pending_, tret);
  pending_flag_ = flag;
  if (flag < 0) return flag;
  t_ = tret;
  t_reached = tret;
  return 0;
}

int Engine::step_finish() noexcept {
  const int flag = pending_flag_;
  pending_flag_ = 0;
  if (flag != CV_SUCCESS) return handle_return(flag, root_pending_);
  if (solver_.total_steps() > options_.max_total_steps) return kTooManyTotalSteps;
  // the safety net of run_to, at every step end
  if (system_->check_consistency(t_, solver_.state(), log_)) {
    if (restart() < 0) return kRestartFailed;
  }
  return 0;
}

SolverStats Engine::stats() noexcept {
  SolverStats s = solver_.stats();
  s.events = log_.count;
  s.restarts = restarts_;
  s.command_stops = stops_;
  return s;
}

std::string Engine::failure(int flag) const {
  std::string why;
  if (flag == kTooManyTotalSteps) {
    why = "more than solver.max_total_steps = " + std::to_string(options_.max_total_steps) +
          " steps: the contact is chattering or very stiff; raise the limit, reduce the contact "
          "damping D or stiffness K, or lower solver.zeno_events";
  } else if (flag == kRestartFailed) {
    why = "the integrator could not restart after an event (non-finite state?)";
  } else {
    why = describe_cvode_failure(flag);
  }
  std::string msg = "plant simulation failed at " + system_->describe(t_, solver_.state()) +
                    ": " + why;
  if (!solver_.message().empty()) msg += " [" + solver_.message() + "]";
  return msg;
}

}  // namespace clearshape::plant::detail
