#pragma once
// Continuous-time SISO transfer function H(s) = N(s)/D(s), coefficients in DESCENDING powers
// of s (SciPy/MATLAB order, see polynomial.hpp). Stored normalized: D monic, leading zeros
// trimmed. Must be proper (deg N ≤ deg D). Zeros may lie in the right half plane.
#include <complex>
#include <span>
#include <vector>

#include "clearshape/lti/modes.hpp"
#include "clearshape/lti/polynomial.hpp"
#include "clearshape/lti/state_space.hpp"

namespace clearshape::lti {

class TransferFunction {
 public:
  /// Throws InvalidArgument on non-finite coefficients, a zero denominator or an improper H.
  TransferFunction(Polynomial numerator, Polynomial denominator);
  /// H(s) = gain · Π(s − zᵢ) / Π(s − pᵢ); complex roots in conjugate pairs.
  static TransferFunction from_zeros_poles_gain(std::span<const std::complex<double>> zeros,
                                                std::span<const std::complex<double>> poles,
                                                double gain);

  const Polynomial& numerator() const noexcept { return numerator_; }
  const Polynomial& denominator() const noexcept { return denominator_; }
  int order() const noexcept { return degree(denominator_); }
  int relative_degree() const noexcept { return order() - degree(numerator_); }

  std::vector<std::complex<double>> poles() const;  ///< roots of D, sorted
  std::vector<std::complex<double>> zeros() const;  ///< roots of N, sorted
  std::vector<OscillatoryMode> oscillatory_modes() const;
  /// H(0) = N(0)/D(0); ±infinity for a pole at the origin (NaN if N(0) = 0 too).
  double dc_gain() const noexcept;
  /// H(jω).
  std::complex<double> frequency_response(double frequency_rad_s) const noexcept;
  std::vector<std::complex<double>> frequency_response(std::span<const double> frequencies_rad_s) const;

  /// Controller canonical form exactly as scipy.signal.tf2ss: A = [−a1 … −an; I 0],
  /// B = e1, C = b − b0·a (tail), D = b0.
  StateSpace controllable_canonical() const;
  /// The controller canonical form scaled by a diagonal power-of-two similarity (Osborne
  /// balancing of [A B; C 0], as MATLAB ssbal): same H(s), far better conditioned when the
  /// coefficients span many decades.
  StateSpace state_space() const;

 private:
  Polynomial numerator_;
  Polynomial denominator_;
};

/// Diagonal power-of-two balancing of a SISO state-space model (rounding-free similarity).
StateSpace balance(const StateSpace& model);

}  // namespace clearshape::lti
