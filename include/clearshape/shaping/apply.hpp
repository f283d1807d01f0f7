#pragma once
// Offline shaping of a sampled command: y(t) = Σ Aᵢ·u(t − tᵢ) (Fig. 1.14–1.15 convolution).
// The sampled input is taken as piecewise linear between samples, so an impulse time between
// two samples is applied exactly (split over the two neighbouring samples), never rounded.
#include <cstddef>
#include <vector>

#include "clearshape/core/series.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::shaping {

/// A shaper discretised at a sample time: y[k] = Σ taps[j].weight · u[k − taps[j].delay].
struct DiscreteTap {
  std::size_t delay_samples = 0;
  double weight = 0.0;
};
/// Each impulse at t = (m + f)·Ts, 0 <= f < 1, becomes weights A(1−f) at m and A·f at m+1
/// (first-order hold); taps at equal delays are merged.
std::vector<DiscreteTap> discretize(const Shaper& shaper, double sample_time_s);

/// Shapes `input`. Before the first sample the input is held at its first value. With
/// `extend` the output is longer by the shaper's duration (rounded up to whole samples), with
/// the input held at its last value, so the shaped command reaches the final value.
UniformSeries shape_offline(const Shaper& shaper, const UniformSeries& input, bool extend = true);

}  // namespace clearshape::shaping
