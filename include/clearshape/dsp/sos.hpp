#pragma once
// Digital filters as cascaded second-order sections (SOS), the layout of scipy.signal's `sos`
// arrays: each row is [b0, b1, b2, a0, a1, a2] and the filter is the product of the rows'
// H(z) = (b0 + b1 z⁻¹ + b2 z⁻²) / (a0 + a1 z⁻¹ + a2 z⁻²).
// SosDesign is the immutable, validated design; StreamingSosFilter (sosfilt.hpp) runs it.
#include <complex>
#include <cstddef>
#include <vector>

namespace clearshape::dsp {

/// One biquad, coefficients in scipy's row order.
struct Section {
  double b0 = 1.0, b1 = 0.0, b2 = 0.0;
  double a0 = 1.0, a1 = 0.0, a2 = 0.0;
};

/// Zeros, poles and gain of a digital filter (z-plane), as scipy's output='zpk'.
struct Zpk {
  std::vector<std::complex<double>> zeros;
  std::vector<std::complex<double>> poles;
  double gain = 1.0;
};

/// A validated cascade of second-order sections at a sample rate.
class SosDesign {
 public:
  /// Throws InvalidArgument if `sections` is empty, a coefficient is not finite, a0 == 0, or
  /// sample_rate_hz is not > 0. Each section is normalized to a0 = 1 (scipy requires it).
  SosDesign(std::vector<Section> sections, double sample_rate_hz);

  const std::vector<Section>& sections() const noexcept { return sections_; }
  std::size_t section_count() const noexcept { return sections_.size(); }
  double sample_rate_hz() const noexcept { return sample_rate_hz_; }

  /// H(e^{jωT}) at `frequency_hz` (as scipy.signal.sosfreqz with fs).
  std::complex<double> response(double frequency_hz) const noexcept;
  /// |H| at `frequency_hz`.
  double magnitude(double frequency_hz) const noexcept { return std::abs(response(frequency_hz)); }
  /// H(1) = Π Σb/Σa, the steady-state gain for a constant input.
  double dc_gain() const noexcept;

 private:
  std::vector<Section> sections_;
  double sample_rate_hz_ = 1.0;
};

/// Groups zeros and poles into second-order sections like scipy.signal.zpk2sos(z, p, k) with its
/// default digital pairing 'nearest': poles closest to the unit circle go to the last sections,
/// each pole pair takes its nearest zeros, an odd count gets a pole and zero at the origin, and
/// the gain goes into the first section; unequal counts are padded with roots at the origin.
/// Complex values must come in conjugate pairs (relative tolerance 100·eps, as scipy's
/// _cplxreal); throws InvalidArgument otherwise. No roots at all gives one section [k,0,0,1,0,0].
std::vector<Section> zpk_to_sos(const Zpk& zpk);

}  // namespace clearshape::dsp
