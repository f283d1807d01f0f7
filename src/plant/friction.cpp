#include "clearshape/plant/friction.hpp"

#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::plant {

void Friction::validate(const char* owner) const {
  const std::string p = std::string(owner) + ".";
  require_non_negative(p + "viscous", viscous);
  require_non_negative(p + "coulomb", coulomb);
  require_non_negative(p + "static_level", static_level);
  require_positive(p + "stribeck_rate", stribeck_rate);
  require_positive(p + "regularization_rate", regularization_rate,
                   "the tanh scale v_t must be > 0 (e.g. 1e-3 of the typical rate)");
}

FrictionValue Friction::evaluate(double v) const noexcept {
  FrictionValue out;
  out.force = -viscous * v;
  out.d_rate = -viscous;
  if (coulomb > 0.0 || static_level > 0.0) {
    // level(v) = F_c + (F_s − F_c) exp(−(v/v_S)²) (Stribeck); sign by tanh(v/v_t) (regularized)
    double level = coulomb;
    double d_level = 0.0;
    if (static_level > coulomb) {
      const double r = v / stribeck_rate;
      const double ex = std::exp(-r * r);
      level += (static_level - coulomb) * ex;
      d_level = (static_level - coulomb) * ex * (-2.0 * r / stribeck_rate);
    }
    const double th = std::tanh(v / regularization_rate);
    out.force -= level * th;
    out.d_rate -= d_level * th + level * (1.0 - th * th) / regularization_rate;
  }
  return out;
}

void CoulombContactFriction::validate(const char* owner) const {
  const std::string p = std::string(owner) + ".";
  require_non_negative(p + "coefficient", coefficient);
  require_positive(p + "regularization_rate", regularization_rate,
                   "the tanh scale v_t must be > 0, e.g. 1e-3 m/s");
}

FrictionValue CoulombContactFriction::factor(double v) const noexcept {
  const double th = std::tanh(v / regularization_rate);  // thesis Eq. 2.9, regularized
  return {coefficient * th, coefficient * (1.0 - th * th) / regularization_rate};
}

}  // namespace clearshape::plant
