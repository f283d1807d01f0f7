#pragma once
// Digital Butterworth filters as second-order sections (thesis §3.3: the differentiated encoder
// angle is filtered by a 4th-order low-pass Butterworth with a 30 rad/s passband edge).
//
// Convention: exactly scipy.signal.butter(N, Wn, btype, fs=fs, output='sos') — a digital design
// by the bilinear transform of the analog prototype with the cutoff pre-warped, so |H| = 1/√2
// (−3 dB) exactly at the requested cutoff frequency(ies) — followed by zpk2sos with 'nearest'
// pairing (see sos.hpp). Coefficients agree with SciPy 1.10 to ~1e-15 (tests/dsp/test_butterworth).
// The cutoff is the −3 dB frequency, in Hz (or rad/s through the *_rad_s helpers; the
// conversion is f = ω / 2π). MATLAB's butter(N, Wn) with Wn = f / (fs/2) is the same filter.
#include "clearshape/dsp/sos.hpp"

namespace clearshape::dsp {

enum class BandType { lowpass, highpass, bandpass };

/// A Butterworth specification. For lowpass/highpass only `cutoff_hz` is used; for bandpass
/// the passband is [cutoff_hz, cutoff_high_hz] and the filter has 2·order poles (as scipy).
struct ButterworthSpec {
  int order = 4;                      ///< 1 … 16
  BandType type = BandType::lowpass;
  double cutoff_hz = 1.0;             ///< −3 dB edge; 0 < cutoff_hz < sample_rate_hz / 2
  double cutoff_high_hz = 0.0;        ///< bandpass upper −3 dB edge; cutoff_hz < it < Nyquist
  double sample_rate_hz = 1000.0;     ///< > 0
};

inline constexpr int kMaxButterworthOrder = 16;

/// Zeros, poles and gain of the digital design (scipy output='zpk'). Throws InvalidArgument
/// naming the parameter, value and allowed range when the spec is out of range.
Zpk butter_zpk(const ButterworthSpec& spec);
/// The design as second-order sections (scipy output='sos').
SosDesign butter(const ButterworthSpec& spec);

SosDesign butter_lowpass(int order, double cutoff_hz, double sample_rate_hz);
SosDesign butter_highpass(int order, double cutoff_hz, double sample_rate_hz);
SosDesign butter_bandpass(int order, double low_hz, double high_hz, double sample_rate_hz);
/// Cutoff given as an angular frequency in rad/s (converted with f = ω / 2π).
SosDesign butter_lowpass_rad_s(int order, double cutoff_rad_s, double sample_rate_hz);
SosDesign butter_highpass_rad_s(int order, double cutoff_rad_s, double sample_rate_hz);

}  // namespace clearshape::dsp
