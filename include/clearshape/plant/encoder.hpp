#pragma once
// Incremental quadrature encoder on the motor (thesis §3.2: APM-SB04AEK2, "Inc. 3000 P/R").
// Convention: `lines_per_revolution` pulses per revolution on each of the A and B channels;
// the counter decodes ×1, ×2 or ×4 edges. Default: 3000 lines decoded ×4 = 12000 counts/rev,
// resolution Δ = 2π/12000 rad = 0.03°. (With ×1, Δ = 2π/3000 = 0.12°.)
// count = floor((θ − θ_zero)/Δ), the counter having been zeroed at θ_zero.
// A small value object; every member is noexcept and allocation-free.
#include <cstdint>

namespace clearshape::plant {

enum class Decoding : std::uint8_t { x1 = 1, x2 = 2, x4 = 4 };

struct EncoderConfig {
  int lines_per_revolution = 3000;
  Decoding decoding = Decoding::x4;
  double zero_angle_rad = 0.0;
};

class Encoder {
 public:
  /// Throws InvalidArgument for lines_per_revolution < 1 or a non-finite zero angle.
  explicit Encoder(const EncoderConfig& config = {});

  std::int64_t counts_per_revolution() const noexcept { return counts_per_revolution_; }
  double resolution_rad() const noexcept { return resolution_rad_; }
  /// floor((θ − θ_zero)/Δ); saturates at ±2^62 for non-finite or huge angles.
  std::int64_t count(double angle_rad) const noexcept;
  /// The angle a count reports: θ_zero + count·Δ (the lower edge of the count's interval).
  double angle_rad(std::int64_t count) const noexcept;
  /// angle_rad(count(θ)): the measured angle, θ − Δ < measured ≤ θ.
  double measure(double angle) const noexcept { return angle_rad(count(angle)); }
  const EncoderConfig& config() const noexcept { return config_; }

 private:
  EncoderConfig config_;
  std::int64_t counts_per_revolution_ = 0;
  double resolution_rad_ = 0.0;
};

}  // namespace clearshape::plant
