#include "clearshape/lti/modes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "clearshape/core/units.hpp"

namespace clearshape::lti {

double OscillatoryMode::damped_frequency_rad_s() const noexcept {
  // ωd = ωn √(1 − ζ²)
  return natural_frequency_rad_s * std::sqrt(std::max(0.0, 1.0 - damping_ratio * damping_ratio));
}
double OscillatoryMode::natural_frequency_hz() const noexcept { return rad_s_to_hz(natural_frequency_rad_s); }
double OscillatoryMode::period_s() const noexcept {
  const double wd = damped_frequency_rad_s();
  return wd > 0.0 ? kTwoPi / wd : std::numeric_limits<double>::infinity();
}

std::vector<OscillatoryMode> oscillatory_modes(std::span<const std::complex<double>> poles,
                                               double imag_tolerance) {
  std::vector<OscillatoryMode> modes;
  for (const auto& p : poles) {
    const double magnitude = std::abs(p);
    if (!(magnitude > 0.0) || !(p.imag() > imag_tolerance * magnitude)) continue;
    // s = −ζωn + jωd  ⇒  ωn = |s|, ζ = −Re(s)/|s|
    modes.push_back({magnitude, -p.real() / magnitude});
  }
  std::sort(modes.begin(), modes.end(), [](const auto& x, const auto& y) {
    return x.natural_frequency_rad_s < y.natural_frequency_rad_s;
  });
  return modes;
}

}  // namespace clearshape::lti
