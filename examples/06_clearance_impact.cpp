// One impact of the link against the clearance stop, with a Kelvin–Voigt law tuned for e = 0.8
// and a Hunt–Crossley law with nominal e = 0.8. Prints the effective restitution read from the
// contact events and checks it: KV returns e exactly, Hunt–Crossley 0.833 (its known bias,
// docs/design.md §5).
#include <cmath>
#include <cstdio>

#include "clearshape/plant/plant.hpp"

namespace cp = clearshape::plant;

// e_eff = separation rate / approach rate of the first contact (the motor stays at rest).
double impact_restitution(const cp::ContactLaw& law, double inertia_kg_m2) {
  cp::PlantModel model;
  model.drive = cp::DriveModel::thesis_position_mode();
  model.link.inertia_kg_m2 = inertia_kg_m2;
  cp::TorsionalClearance joint;
  joint.half_play_rad = 0.01;  // ±0.57°
  joint.law = law;
  model.joint = joint;
  cp::SimulationOptions options;
  options.duration_s = 0.05;
  options.solver.relative_tolerance = 1e-10;
  options.solver.angle_tolerance_rad = 1e-13;
  options.initial.link_rate_rad_s = 1.0;  // the link spins inside the play towards +β
  const cp::Simulation run = cp::simulate(model, cp::Command::constant(0.0), options);
  double approach = 0.0, separation = 0.0;
  for (const cp::ContactEvent& e : run.events) {
    if (e.kind == cp::EventKind::onset && approach == 0.0) approach = e.rate;
    if (e.kind == cp::EventKind::separation && separation == 0.0) separation = -e.rate;
  }
  std::printf("  %-22s approach %.4f rad/s, rebound %.4f rad/s, %ld steps, %zu events\n",
              std::string(law.kind_name()).c_str(), approach, separation, run.stats.steps,
              run.events.size());
  return approach > 0.0 ? separation / approach : 0.0;
}

int main() {
  const double inertia = 2e-3;  // kg·m²
  const double e = 0.8;
  // Kelvin–Voigt: k = 500 N·m/rad, c = 2 ζ(e) √(k J) (exact for the raw law)
  const auto kv = cp::ContactLaw::kelvin_voigt_restitution(500.0, e, inertia);
  // Hunt–Crossley: K = 5e4 N·m/rad^1.5, F = K δ^1.5 (1 + 1.5(1 − e) δ̇/δ̇⁻)
  const auto hc = cp::ContactLaw::hysteresis(cp::Hysteresis::hunt_crossley, 5e4, 1.5, e);
  std::printf("single impact of a %.0e kg·m² link, nominal e = %.2f\n", inertia, e);
  const double e_kv = impact_restitution(kv, inertia);
  const double e_hc = impact_restitution(hc, inertia);
  std::printf("e_eff Kelvin-Voigt  = %.6f (expected %.6f)\n", e_kv, e);
  std::printf("e_eff Hunt-Crossley = %.6f (expected 0.833 ± 0.002)\n", e_hc);
  const bool ok = std::abs(e_kv - e) < 1e-6 && std::abs(e_hc - 0.833) < 0.002;
  std::printf("%s\n", ok ? "OK" : "MISMATCH");
  return ok ? 0 : 1;
}
