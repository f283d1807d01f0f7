#pragma once
// Peak picking on sampled curves (a spectrum, a frequency response) for mode identification.
// The selection follows scipy.signal.find_peaks: local maxima (a flat top counts once, at its
// middle sample, rounding down), then minimum height, minimum distance (higher peaks win),
// then minimum prominence (scipy.signal.peak_prominences with an unlimited window).
#include <cstddef>
#include <limits>
#include <span>
#include <vector>

#include "clearshape/dsp/welch.hpp"

namespace clearshape::dsp {

struct PeakOptions {
  double min_height = -std::numeric_limits<double>::infinity();  ///< keep peaks with value ≥ this (scipy height)
  std::size_t min_distance = 1;     ///< samples between kept peaks (scipy distance, ≥ 1)
  double min_prominence = 0.0;      ///< keep peaks with prominence ≥ this (scipy prominence)
};

struct Peak {
  std::size_t index = 0;   ///< sample index of the peak
  double height = 0.0;     ///< value at index
  double prominence = 0.0; ///< height above the higher of the two surrounding minima
};

/// Peaks of `values` in index order. Throws InvalidArgument if min_distance == 0 or a value is
/// not finite.
std::vector<Peak> find_peaks(std::span<const double> values, const PeakOptions& options = {});

/// A spectral peak: bin frequency and power, and the vertex of the parabola through the peak bin
/// and its two neighbours (a sub-bin frequency estimate; equals the bin at the ends).
struct SpectralPeak {
  double frequency_hz = 0.0;
  double power = 0.0;
  double prominence = 0.0;
  double interpolated_frequency_hz = 0.0;
  std::size_t bin = 0;
};

/// The `max_count` highest peaks of a spectrum (all if max_count == 0), highest first.
std::vector<SpectralPeak> spectral_peaks(const Spectrum& spectrum, const PeakOptions& options = {},
                                         std::size_t max_count = 0);

}  // namespace clearshape::dsp
