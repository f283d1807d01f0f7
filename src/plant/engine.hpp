#pragma once
// Internal: the event-driven integration loop shared by simulate(), Simulator and
// single_impact(): CVODE towards an output time, handling contact events (roots) and command
// discontinuities (stop times) on the way.
#include <memory>
#include <string>
#include <vector>

#include "clearshape/plant/simulation.hpp"
#include "cvode_solver.hpp"
#include "joint_system.hpp"

namespace clearshape::plant::detail {

std::unique_ptr<JointSystem> make_system(const PlantModel& model, const SolverOptions& options);

class Engine {
 public:
  Engine(const PlantModel& model, const SolverOptions& options, std::vector<ContactEvent>* events,
         bool bounded_events);

  /// Initial state at t = 0 with the input already set in system().input.
  void start(const InitialState& initial);
  /// Integrates to tout (> current time). Returns 0, or a negative CVODE flag (message()).
  int run_to(double tout) noexcept;
  /// Dense-output stepping for offline runs, in two phases so that the caller can read the
  /// step's interpolant before an event changes the mode or restarts the integrator:
  /// step_begin takes one internal step towards t_end (stopping at events, command stops and
  /// t_end) and returns the reached time in t_reached; interpolate(t) is then valid for t in
  /// the step; step_finish handles the event or stop there (as run_to does). Both return 0 or
  /// a negative CVODE flag (failure()).
  int step_begin(double t_end, double& t_reached) noexcept;
  int step_finish() noexcept;
  /// y(t) within the last step (null if t is outside it).
  const double* interpolate(double t) noexcept { return solver_.interpolate(t); }
  /// Sets the held input at the current time and restarts if it changed.
  int set_held_input(double value) noexcept;
  /// Sets the next command discontinuity (stop time), +inf for none.
  void set_next_stop(double t_stop) noexcept { solver_.set_stop_time(t_stop); }
  /// Called at a stop time; the callback updates the input; restarts the integrator.
  using StopHandler = void (*)(void* context, double t, JointSystem& system);
  void on_stop(StopHandler handler, void* context) noexcept { stop_handler_ = handler; stop_context_ = context; }

  double time_s() const noexcept { return t_; }
  const double* state() const noexcept { return solver_.state(); }
  JointSystem& system() noexcept { return *system_; }
  const JointSystem& system() const noexcept { return *system_; }
  SolverStats stats() noexcept;
  long events() const noexcept { return log_.count; }
  /// Full failure description (flag, time, state, remedy).
  std::string failure(int flag) const;

 private:
  int restart() noexcept;
  std::unique_ptr<JointSystem> system_;
  CvodeSolver solver_;
  EventLog log_;
  SolverOptions options_;
  double t_ = 0.0;
  long restarts_ = 0;
  long stops_ = 0;
  std::vector<int> found_;
  StopHandler stop_handler_ = nullptr;
  void* stop_context_ = nullptr;
  long steps_before_ = 0;
  int pending_flag_ = 0;      // step_begin's CVODE flag, handled by step_finish
  bool root_pending_ = false; // a root return handled without restarting (see run_to)
  int handle_return(int flag, bool& root_pending) noexcept;
  template <class Advance>
  int advance_after_root(Advance&& advance, bool& root_pending, double& tret) noexcept;
};

}  // namespace clearshape::plant::detail
