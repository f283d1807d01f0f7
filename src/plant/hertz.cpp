#include "clearshape/plant/hertz.hpp"

#include <cmath>
#include <numbers>

#include "clearshape/core/error.hpp"

namespace clearshape::plant {

namespace {
void check_material(const Material& m, const char* name) {
  require_positive(std::string(name) + ".youngs_modulus_pa", m.youngs_modulus_pa,
                   "steel is 207e9 Pa");
  require_in_open(std::string(name) + ".poisson_ratio", m.poisson_ratio, -1.0, 0.5,
                  "steel is 0.3");
}
}  // namespace

double effective_radius_external(double r1, double r2) {
  require_positive("radius_1_m", r1);
  require_positive("radius_2_m", r2);
  return r1 * r2 / (r1 + r2);  // thesis Eq. 2.6
}

double effective_radius_internal(double journal, double bearing) {
  require_positive("journal_radius_m", journal);
  require_positive("bearing_radius_m", bearing);
  if (!(bearing > journal)) {
    throw_invalid("bearing_radius_m", bearing, "> journal_radius_m",
                  "the bearing bore must be larger than the journal (radial clearance > 0)");
  }
  return journal * bearing / (bearing - journal);  // concave–convex contact (clearance_sim §3.2)
}

double effective_modulus_pa(const Material& a, const Material& b) {
  check_material(a, "material_1");
  check_material(b, "material_2");
  return 1.0 / ((1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus_pa +
                (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus_pa);
}

double compliance_parameter(const Material& m) {
  check_material(m, "material");
  return (1.0 - m.poisson_ratio * m.poisson_ratio) / (std::numbers::pi * m.youngs_modulus_pa);  // Eq. 2.6
}

double hertz_stiffness(const Material& a, const Material& b, double effective_radius_m) {
  require_positive("effective_radius_m", effective_radius_m);
  return 4.0 / 3.0 * effective_modulus_pa(a, b) * std::sqrt(effective_radius_m);  // Hertz
}

double hertz_stiffness_thesis(double h1, double h2, double effective_radius_m) {
  require_positive("h1", h1);
  require_positive("h2", h2);
  require_positive("effective_radius_m", effective_radius_m);
  return 4.0 / (3.0 * std::numbers::pi * (h1 + h2)) * std::sqrt(effective_radius_m);  // Eq. 2.5
}

double torsional_stiffness(double linear_stiffness, double exponent, double radius_m) {
  require_positive("linear_stiffness", linear_stiffness);
  require_in_closed("exponent", exponent, 1.0, 10.0);
  require_positive("radius_m", radius_m);
  return linear_stiffness * std::pow(radius_m, exponent + 1.0);  // τ = r·K (r δ)ⁿ
}

double torsional_damping(double linear_damping, double radius_m) {
  require_non_negative("linear_damping", linear_damping);
  require_positive("radius_m", radius_m);
  return linear_damping * radius_m * radius_m;  // τ = r·D·(r δ̇)
}

}  // namespace clearshape::plant
