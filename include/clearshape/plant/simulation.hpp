#pragma once
// Simulation of the plant (drive + link + clearance joint) with SUNDIALS CVODE
// (docs/design.md §1): BDF with a dense linear solver (or Adams for non-stiff checks),
// analytic Jacobian for the torsional joint (difference quotients for the planar one),
// CVodeRootInit for contact onset/separation, CVodeReInit after every mode change that makes
// the right-hand side jump, output at a fixed sample rate from CVODE's dense output
// (stop times only at command discontinuities).
//
// Modes per contact: free → contact (δ̇⁻ latched; below the law's floor it latches 0, i.e.
// χ = 0) → free. An impulse law bounces (δ̇⁺ = −e δ̇⁻) or, for approaches slower than its static
// rate, locks the link to the shaft until the constraint torque would pull. The Zeno guard
// (`zeno_events` onsets within `zeno_window_s`) switches to persistent contact (continuous laws:
// χ = 0 and the onset/separation roots replaced by a release root δ + release_gap = 0;
// impulse laws: lock).
// A start exactly on the boundary at rest is in contact if the link accelerates into the stop;
// an onset or separation the root finder could not see (a root function exactly 0 at a
// restart) is processed at the next output time.
// Default tolerances (rtol 1e-7, 1e-10 rad, 1e-8 rad/s) resolve the thesis-scale responses far
// below the sensors' quantization; the physics tests tighten them.
//
// Failure (step-size collapse, too many steps, non-finite state) throws RuntimeError naming
// the time, the state and what to change.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "clearshape/core/status.hpp"
#include "clearshape/plant/command.hpp"
#include "clearshape/plant/joint.hpp"

namespace clearshape::plant {

enum class Integrator : std::uint8_t {
  bdf,    ///< stiff (default): thesis D values make the damping term stiff
  adams,  ///< non-stiff Adams–Moulton with fixed-point iteration (elastic impacts)
};

struct SolverOptions {
  Integrator integrator = Integrator::bdf;
  double relative_tolerance = 1e-7;
  double angle_tolerance_rad = 1e-10;   ///< absolute tolerance of angles (and drive states)
  double rate_tolerance_rad_s = 1e-8;   ///< absolute tolerance of rates
  double length_tolerance_m = 1e-12;    ///< planar: pivot position
  double speed_tolerance_m_s = 1e-9;    ///< planar: pivot velocity
  double max_step_s = 0.0;              ///< 0: unlimited
  long max_steps_per_output = 200000;   ///< CVODE mxstep between two outputs
  long max_total_steps = 50000000;
  bool analytic_jacobian = true;        ///< torsional only; planar uses difference quotients
  /// Include the energy integrals (dissipated energy, shaft work) in the error test, so the
  /// energy balance closes to the tolerances (costs extra steps at impacts); otherwise they are
  /// integrated alongside without error control.
  bool control_energy_error = true;
  int zeno_events = 50;                 ///< onsets within zeno_window_s that mean persistence
  double zeno_window_s = 1e-3;
  /// Release distance in persistent mode as a fraction of the play (β, or c): the contact is
  /// left when δ < −release_gap_fraction·β.
  double release_gap_fraction = 1e-3;
  void validate() const;
};

struct SimulationOptions {
  double duration_s = 1.0;
  double output_rate_hz = 1000.0;  ///< samples at k/output_rate_hz, k = 0…, t ≤ duration
  SolverOptions solver{};
  InitialState initial{};
  bool record_events = true;
  /// Record the energy columns (kinetic … drive_work, energy_balance_j); off leaves them empty.
  bool record_energy = true;
  void validate() const;
};

enum class ContactMode : std::uint8_t {
  free,        ///< inside the play
  contact,     ///< impact phase of a continuous law (δ̇⁻ latched)
  persistent,  ///< persistent contact (χ = 0 / Zeno guard), release root active
  locked,      ///< impulse law: link locked to the shaft at the stop
};
std::string_view to_string(ContactMode mode) noexcept;

enum class EventKind : std::uint8_t {
  onset,        ///< δ rises through 0 (continuous law)
  separation,   ///< δ falls through 0
  impact,       ///< impulse applied (impulse law)
  lock,         ///< entered locked / persistent contact
  release,      ///< left locked / persistent contact
  rate_switch,  ///< δ̇ = 0 inside a contact (Eq. 2.2–2.3 unloading)
  zeno,         ///< Zeno guard tripped
};
std::string_view to_string(EventKind kind) noexcept;

struct ContactEvent {
  double time_s = 0.0;
  EventKind kind = EventKind::onset;
  int side = 0;                  ///< torsional: +1 (φ > β) or −1; planar: 0
  double rate = 0.0;             ///< δ̇ at the event (approach > 0), rad/s or m/s
  double rate_after = 0.0;       ///< δ̇ after an impulse
};

struct SolverStats {
  long steps = 0;
  long rhs_evaluations = 0;
  long jacobian_evaluations = 0;
  long root_evaluations = 0;
  long error_test_failures = 0;
  long nonlinear_convergence_failures = 0;
  long events = 0;          ///< onsets, separations, impacts, locks, releases
  long restarts = 0;        ///< CVodeReInit calls
  long command_stops = 0;   ///< stops at command discontinuities
};

/// Time series of a run, sampled at output_rate_hz (index k ↔ time_s[k]). Angles in rad,
/// rates in rad/s, torques in N·m, energies in J. Planar-only series are empty for the
/// torsional joint.
struct Simulation {
  std::vector<double> time_s;
  std::vector<double> command;            ///< command units, after the drive's delay shift
  std::vector<double> motor_angle_rad;
  std::vector<double> motor_rate_rad_s;
  std::vector<double> link_angle_rad;
  std::vector<double> link_rate_rad_s;
  std::vector<double> relative_angle_rad; ///< φ = θ_link − θ_motor
  std::vector<double> contact_torque_n_m; ///< torque of the contact on the link (planar:
                                          ///< moment of the friction force about the pivot)
  std::vector<double> penetration;        ///< δ (rad torsional, m planar); < 0 inside the play
  std::vector<double> normal_force;       ///< F ≥ 0 of the law (N·m torsional, N planar)
  std::vector<std::uint8_t> mode;         ///< ContactMode per sample
  // planar
  std::vector<double> pivot_x_m, pivot_y_m;  ///< p (bearing centre w.r.t. the journal)
  std::vector<double> friction_force_n;      ///< F_T along t on the link
  // energies (link system: kinetic + gravity + contact spring; work terms from t = 0)
  std::vector<double> kinetic_energy_j;
  std::vector<double> potential_energy_j;   ///< gravity
  std::vector<double> contact_energy_j;     ///< V(δ) of the law
  std::vector<double> dissipated_energy_j;  ///< ∫ contact damping + friction + impulses
  std::vector<double> drive_work_j;         ///< ∫ power the shaft delivers to the link

  std::vector<ContactEvent> events;
  SolverStats stats{};
  std::size_t size() const noexcept { return time_s.size(); }
  /// E_kin + E_pot + V − W_drive + W_diss: constant (its t = 0 value) to integration accuracy.
  double energy_balance_j(std::size_t k) const;
};

/// Runs the plant under a command; throws RuntimeError on integration failure and
/// InvalidArgument on a bad model or options.
Simulation simulate(const PlantModel& model, const Command& command,
                    const SimulationOptions& options);

/// Streaming form (for the simulated rig): a preallocated CVODE integrator advanced tick by
/// tick with a command held constant over each tick. advance() is noexcept and returns
/// Status::device_error on integration failure (error_message() says why) and
/// Status::not_finite for a non-finite command.
class Simulator {
 public:
  struct State {
    double time_s = 0.0;
    double command = 0.0;
    double motor_angle_rad = 0.0;
    double motor_rate_rad_s = 0.0;
    double link_angle_rad = 0.0;
    double link_rate_rad_s = 0.0;
    double relative_angle_rad = 0.0;
    double penetration = 0.0;
    double normal_force = 0.0;
    double contact_torque_n_m = 0.0;
    ContactMode mode = ContactMode::free;
  };

  /// Validates and allocates. `initial_command` sets the drive's rest state.
  Simulator(const PlantModel& model, const SolverOptions& options = {},
            const InitialState& initial = {}, double initial_command = 0.0);
  ~Simulator();
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) noexcept;
  Simulator(const Simulator&) = delete;
  Simulator& operator=(const Simulator&) = delete;

  /// Integrates to t_end_s with the command held at `command` (a change is a discontinuity:
  /// the integrator restarts). t_end_s must exceed time_s(). Events go to events().
  Status advance(double t_end_s, double command) noexcept;
  /// Restarts from the initial state at t = 0.
  void reset(const InitialState& initial, double initial_command = 0.0);

  const State& state() const noexcept;
  double time_s() const noexcept { return state().time_s; }
  const SolverStats& stats() const noexcept;
  /// Events so far (capacity reserved at construction; older events are dropped beyond it).
  const std::vector<ContactEvent>& events() const noexcept;
  void clear_events() noexcept;
  const std::string& error_message() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// One impact of a body of effective mass (inertia) m against a fixed stop under `law`,
/// starting at δ = 0 with approach rate v₀ > 0 (docs/design.md §5).
struct SingleImpact {
  double restitution = 0.0;        ///< e_eff = −δ̇⁺/v₀ (0 if stuck)
  double contact_time_s = 0.0;     ///< until δ returns to 0 (or until rest if stuck)
  double max_penetration = 0.0;
  double max_force = 0.0;
  double min_force = 0.0;          ///< < 0 only for the raw policy (pulling)
  bool separated = false;          ///< false: came to rest inside the penetration zone
  double dissipated_energy = 0.0;  ///< ½ m v₀² − ½ m δ̇⁺²
};
SingleImpact single_impact(const ContactLaw& law, double effective_mass, double approach_rate,
                           const SolverOptions& options = {});

}  // namespace clearshape::plant
