#pragma once
// Cross-spectral density, frequency-response estimate and coherence by Welch averaging, as
// scipy.signal.csd / coherence and MATLAB's cpsd / tfestimate ('Estimator','H1') / mscohere:
//
//   Pxy(f) = scale · mean over segments of conj(X_s(f)) · Y_s(f)   (one-sided, like welch())
//   H1(f)  = Pxy(f) / Pxx(f)                 (Bendat & Piersol, Random Data, 4th ed., ch. 9)
//   Cxy(f) = |Pxy(f)|² / (Pxx(f) · Pyy(f))   (ibid., ch. 5 and 9), 0 ≤ Cxy ≤ 1
//
// H1 is unbiased by noise on the output and biased low by noise on the input; Cxy is the share of
// the output's power at f that is linearly explained by the input (docs/frf.md).
#include <complex>
#include <cstddef>
#include <span>
#include <vector>

#include "clearshape/dsp/welch.hpp"

namespace clearshape::dsp {

/// A one-sided cross spectrum (scipy.signal.csd): power[k] = Pxy at frequency_hz[k].
struct CrossSpectrum {
  std::vector<double> frequency_hz;
  std::vector<std::complex<double>> power;  ///< unit_x·unit_y/Hz (density) or unit_x·unit_y (spectrum)
  std::size_t segments = 0;
};

/// Pxy = conj(X)·Y averaged over Welch segments (scipy.signal.csd(x, y), same options and
/// defaults as welch()). Throws InvalidArgument when the sizes differ, a sample is not finite or
/// an option is out of range (the message names it and the allowed range).
CrossSpectrum csd(std::span<const double> x, std::span<const double> y, double sample_rate_hz,
                  const WelchOptions& options = {});

/// The H1 frequency-response estimate of output/input with its coherence.
struct FrequencyResponse {
  std::vector<double> frequency_hz;
  std::vector<std::complex<double>> response;  ///< H1 = Pxy/Pxx (output units per input unit); NaN where Pxx = 0
  std::vector<double> coherence;               ///< |Pxy|²/(Pxx·Pyy) in [0, 1]; NaN where Pxx·Pyy = 0
  std::vector<double> input_psd;               ///< Pxx
  std::vector<double> output_psd;              ///< Pyy
  std::size_t segments = 0;
  std::vector<double> magnitude() const;   ///< |H1|
  std::vector<double> phase_deg() const;   ///< arg H1 in degrees, in (−180, 180]
};

/// H1 and coherence of `output` against `input` (same length, sampled at sample_rate_hz).
/// Throws InvalidArgument as csd(), and when the input has no power at any frequency (constant).
FrequencyResponse estimate_frequency_response(std::span<const double> input, std::span<const double> output,
                                              double sample_rate_hz, const WelchOptions& options = {});

/// MATLAB's tfestimate/mscohere default segmentation: a record of `samples` samples cut into 8
/// half-overlapping segments (segment length ⌊samples / 4.5⌋, at least 1).
std::size_t matlab_default_segment_length(std::size_t samples) noexcept;

}  // namespace clearshape::dsp
