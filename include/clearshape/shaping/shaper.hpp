#pragma once
// The immutable, validated design of an input shaper: a sequence of impulses (Eq. 2.21: t1 = 0,
// ΣA = 1). Built by the design functions in design.hpp or from a custom list; run by
// shape_offline() or a StreamingShaper.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

namespace clearshape::shaping {

struct Impulse {
  double time_s = 0.0;
  double amplitude = 0.0;
  friend bool operator==(const Impulse&, const Impulse&) = default;
};

/// A vibration mode: undamped natural frequency and damping ratio.
struct Mode {
  double natural_frequency_rad_s = 0.0;
  double damping_ratio = 0.0;

  static Mode from_hz(double natural_frequency_hz, double damping_ratio);
  double natural_frequency_hz() const noexcept;
  /// ωd = ωn·√(1−ζ²) (Eq. 2.24). Zero for ζ >= 1.
  double damped_frequency_rad_s() const noexcept;
};

class Shaper {
 public:
  enum class Normalize { yes, no };

  /// Validates and stores `impulses`: at least one; all finite; times >= 0 and strictly
  /// increasing; a non-zero amplitude sum. With Normalize::yes the amplitudes are divided by
  /// their sum so that ΣA = 1 (Eq. 2.21). Throws InvalidArgument naming the impulse.
  Shaper(std::string method, std::vector<Impulse> impulses, Normalize normalize = Normalize::yes);

  const std::string& method() const noexcept { return method_; }
  std::span<const Impulse> impulses() const noexcept { return impulses_; }
  std::size_t size() const noexcept { return impulses_.size(); }
  /// Time of the last impulse: the delay the shaper adds to a move.
  double duration_s() const noexcept { return impulses_.back().time_s; }
  double amplitude_sum() const noexcept;
  /// True when every amplitude is >= 0 (a positive shaper never reverses the command).
  bool is_positive() const noexcept;

 private:
  std::string method_;
  std::vector<Impulse> impulses_;
};

/// A positive shaper on a slot grid, as a search over amplitudes builds it: a_k = max(0, x_k) /
/// Σ max(0, x), the zero ones dropped; all zero: a unit impulse at the first slot. `weights` has
/// one value per slot (checked).
Shaper positive_shaper_on_slots(std::string method, std::span<const double> slot_times_s,
                                std::span<const double> weights);

}  // namespace clearshape::shaping
