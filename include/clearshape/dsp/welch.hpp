#pragma once
// Power spectral density by Welch's method (Welch 1967), matching scipy.signal.welch:
// overlapping segments, per-segment detrend, window, FFT (Eigen's unsupported FFT), mean of
// the modified periodograms, one-sided, density (unit²/Hz) or spectrum (unit²) scaling.
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

namespace clearshape::dsp {

/// Periodic ("DFT-even") windows, as scipy.signal.get_window(name, n) (fftbins=True).
enum class Window { hann, hamming, rectangular };
enum class Detrend { none, constant, linear };
enum class SpectralScaling {
  density,   ///< unit²/Hz: scale 1 / (fs · Σw²)
  spectrum,  ///< unit² (power of a sinusoid): scale 1 / (Σw)²
};

struct WelchOptions {
  std::size_t segment_length = 256;           ///< scipy nperseg (its default)
  std::optional<std::size_t> overlap;         ///< scipy noverlap; default segment_length / 2
  std::optional<std::size_t> fft_length;      ///< scipy nfft (≥ segment_length); default = it
  Window window = Window::hann;
  Detrend detrend = Detrend::constant;
  SpectralScaling scaling = SpectralScaling::density;
};

/// A one-sided spectrum: frequency_hz[k] = k · fs / nfft, k = 0 … nfft/2.
struct Spectrum {
  std::vector<double> frequency_hz;
  std::vector<double> power;  ///< unit²/Hz (density) or unit² (spectrum)
  std::size_t segments = 0;   ///< number of averaged segments
  double resolution_hz() const noexcept {
    return frequency_hz.size() > 1 ? frequency_hz[1] - frequency_hz[0] : 0.0;
  }
};

/// Window values of length n (configuration-time helper; also used by welch()).
std::vector<double> make_window(Window window, std::size_t n);

/// Welch PSD of a real signal sampled at sample_rate_hz. Throws InvalidArgument if the signal
/// is shorter than segment_length (scipy would silently shorten the segment), overlap ≥
/// segment_length, fft_length < segment_length, segment_length == 0, a sample is not finite, or
/// sample_rate_hz is not > 0.
Spectrum welch(std::span<const double> input, double sample_rate_hz,
               const WelchOptions& options = {});

}  // namespace clearshape::dsp
