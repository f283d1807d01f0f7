#pragma once
// Oscillatory modes read from complex-conjugate pole pairs: s = −ζωn ± jωn√(1−ζ²).
#include <complex>
#include <span>
#include <vector>

namespace clearshape::lti {

struct OscillatoryMode {
  double natural_frequency_rad_s = 0.0;  ///< ωn = |s|
  double damping_ratio = 0.0;            ///< ζ = −Re(s)/|s| (negative for an unstable pair)
  double damped_frequency_rad_s() const noexcept;  ///< ωd = |Im(s)| = ωn√(1−ζ²)
  double natural_frequency_hz() const noexcept;
  double period_s() const noexcept;                ///< damped period 2π/ωd
};

/// The mode of each complex pole pair (poles with Im(s) > imag_tolerance·|s|, counted once),
/// sorted by natural frequency. Real poles are not oscillatory and are skipped.
std::vector<OscillatoryMode> oscillatory_modes(std::span<const std::complex<double>> poles,
                                               double imag_tolerance = 1e-9);

}  // namespace clearshape::lti
