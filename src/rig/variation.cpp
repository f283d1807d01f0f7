#include "clearshape/rig/variation.hpp"

#include <algorithm>
#include <cmath>

#include "clearshape/core/error.hpp"

namespace clearshape::rig {

void RunVariation::validate() const {
  require_in_closed("truth.variation.position_gain_rel_sigma", position_gain_rel_sigma, 0.0, 0.1);
  require_in_closed("truth.variation.speed_gain_rel_sigma", speed_gain_rel_sigma, 0.0, 0.1);
  require_in_closed("truth.variation.start_latency_max_s", start_latency_max_s, 0.0, 1e-3);
  require_in_closed("truth.variation.analog_noise_v", analog_noise_v, 0.0, 0.1);
  require_in_closed("truth.variation.analog_offset_sigma_v", analog_offset_sigma_v, 0.0, 0.1);
  require_in_closed("truth.variation.flank_damping_rel_sigma", flank_damping_rel_sigma, 0.0, 1.0);
}

RunDraw draw_run_variation(const RunVariation& v, std::mt19937_64& rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const auto z = [&] { return std::clamp(normal(rng), -4.0, 4.0); };
  // Drawn unconditionally and in a fixed order: one σ never shifts another's draw.
  const double z_position = z();
  const double z_speed = z();
  const double u_latency = uniform(rng);
  const double z_offset = z();
  const double z_damping = z();
  RunDraw d;
  d.position_gain = 1.0 + v.position_gain_rel_sigma * z_position;
  d.speed_gain = 1.0 + v.speed_gain_rel_sigma * z_speed;
  d.start_latency_s = v.start_latency_max_s * u_latency;
  d.analog_offset_v = v.analog_offset_sigma_v * z_offset;
  d.flank_damping_factor = std::exp(v.flank_damping_rel_sigma * z_damping);
  return d;
}

}  // namespace clearshape::rig
