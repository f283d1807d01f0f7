#pragma once
// Real-time shaping, one sample at a time. Design/state split: the Shaper is the design; a
// StreamingShaper holds the taps and a ring buffer sized once at construction. step() is
// noexcept, allocation-free and O(number of taps); its output equals shape_offline() to
// rounding.
#include <cstddef>
#include <span>
#include <vector>

#include "clearshape/core/status.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::shaping {

class StreamingShaper {
 public:
  /// Allocates the history for the shaper's duration at sample_time_s (configuration time;
  /// throws InvalidArgument on a bad sample time). `initial_value` fills the history, as if
  /// the input had rested there forever. Linear (first-order-hold) discretisation.
  StreamingShaper(const Shaper& shaper, double sample_time_s, double initial_value = 0.0);
  /// The same from taps made by discretize() (e.g. Discretization::exact_at_mode). Throws
  /// InvalidArgument on no taps, a non-finite weight or a delay beyond 2^26 samples.
  StreamingShaper(std::span<const DiscreteTap> taps, double sample_time_s,
                  double initial_value = 0.0);

  /// Pushes one input sample and writes the shaped output. A non-finite input is rejected
  /// (Status::not_finite): the previous input is held in its place (the history keeps it) and
  /// `output` is the shaped held command — so the output stays finite and continuous.
  Status step(double input, double& output) noexcept;
  /// Convenience form for trusted input (a non-finite input is held all the same).
  double step(double input) noexcept;
  /// Refills the history with `value`.
  void reset(double value = 0.0) noexcept;

  double sample_time_s() const noexcept { return sample_time_s_; }
  std::size_t history_samples() const noexcept { return history_.size(); }
  std::size_t tap_count() const noexcept { return taps_.size(); }
  std::span<const DiscreteTap> taps() const noexcept { return taps_; }

 private:
  std::vector<DiscreteTap> taps_;
  std::vector<double> history_;  // ring buffer; power of two in length
  std::size_t mask_ = 0;
  std::size_t head_ = 0;         // index of the newest sample
  double sample_time_s_ = 0.0;
};

}  // namespace clearshape::shaping
