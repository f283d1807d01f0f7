#pragma once
// Offline shaping of a sampled command: y(t) = Σ Aᵢ·u(t − tᵢ) (Fig. 1.14–1.15 convolution).
// The sampled input is taken as piecewise linear between samples, so an impulse time between
// two samples is applied exactly (split over the two neighbouring samples), never rounded.
#include <cstddef>
#include <span>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::shaping {

/// A shaper discretised at a sample time: y[k] = Σ taps[j].weight · u[k − taps[j].delay].
struct DiscreteTap {
  std::size_t delay_samples = 0;
  double weight = 0.0;
  friend bool operator==(const DiscreteTap&, const DiscreteTap&) = default;
};

/// How an impulse between two samples is split over them.
enum class Discretization {
  /// First-order hold (Vaughan's `digseq`): an impulse A at t = (m + f)·Ts becomes A(1−f) at m
  /// and A·f at m+1 — exactly u(kTs − t) for an input that is linear between samples.
  linear,
  /// Murphy & Watanabe (IEEE T-RA 8(2), 1992): the two weights are chosen so that the impulse's
  /// vibration at one mode (ωn, ζ) is reproduced exactly on the sample grid; the weights are
  /// then rescaled to the shaper's ΣA. V(mode) of the discrete shaper is the continuous one
  /// (0 for a ZV-family design) whatever Ts; DC gain is kept, other frequencies shift slightly.
  exact_at_mode,
};

/// Taps sorted by delay, equal delays merged, zero weights dropped. `mode` is used only by
/// Discretization::exact_at_mode and must then have ωn > 0, ζ in [0, 1) and ωd·Ts in (0, π).
/// Throws InvalidArgument on a bad sample time or mode, or a shaper longer than 2^26 samples.
std::vector<DiscreteTap> discretize(const Shaper& shaper, double sample_time_s,
                                    Discretization method = Discretization::linear,
                                    const Mode& mode = {});

/// The largest tap delay (0 for no taps): the samples a shaped move lasts longer than its input.
std::size_t max_delay_samples(std::span<const DiscreteTap> taps) noexcept;

/// Shapes `input`. Before the first sample the input is held at its first value. With
/// `extend` the output is longer by the shaper's duration (rounded up to whole samples), with
/// the input held at its last value, so the shaped command reaches the final value. Linear
/// (first-order-hold) discretisation. An empty input gives an empty output.
UniformSeries shape_offline(const Shaper& shaper, const UniformSeries& input, bool extend = true);

/// The same with taps from discretize() at input.sample_time_s (e.g. exact_at_mode);
/// `extend` lengthens the output by the largest delay.
UniformSeries shape_offline(std::span<const DiscreteTap> taps, const UniformSeries& input,
                            bool extend = true);

}  // namespace clearshape::shaping
