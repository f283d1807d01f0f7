#include "clearshape/shaping/apply.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::shaping {
namespace {

// A shaper longer than this many samples is a unit mistake (ms given as s), not a design.
constexpr double kMaxDelaySamples = 67108864.0;  // 2^26
// t/Ts within this relative distance of an integer is floating-point noise of the division.
constexpr double kOnGridTolerance = 1e-12;
// Output samples computed per block (8 KiB of doubles stays in L1 while every tap is added).
constexpr std::size_t kBlock = 1024;

struct GridPosition {
  std::size_t m = 0;  // sample at or before the impulse
  double f = 0.0;     // fraction of a sample past m, in [0, 1)
};

GridPosition locate(double time_s, double sample_time_s) {
  const double x = time_s / sample_time_s;
  if (x > kMaxDelaySamples) {
    throw InvalidArgument(fmt::format(
        "shaper duration / sample_time_s = {} / {} = {} samples is out of range; allowed: <= 2^26. "
        "Check the units of the sample time and of the mode frequency.",
        time_s, sample_time_s, x));
  }
  const double nearest = std::round(x);
  if (std::abs(x - nearest) <= kOnGridTolerance * std::max(1.0, nearest)) {
    return {static_cast<std::size_t>(nearest), 0.0};
  }
  const double m = std::floor(x);
  return {static_cast<std::size_t>(m), x - m};
}

void validate_mode(const Mode& mode, double sample_time_s) {
  require_positive("mode.natural_frequency_rad_s", mode.natural_frequency_rad_s,
                   "Discretization::exact_at_mode needs the mode the shaper was designed for.");
  require_in_half_open("mode.damping_ratio", mode.damping_ratio, 0.0, 1.0,
                       "A mode with ζ >= 1 does not oscillate; use Discretization::linear.");
  const double theta = mode.damped_frequency_rad_s() * sample_time_s;
  if (!(theta < std::numbers::pi)) {
    throw_invalid("mode damped frequency × sample_time_s (rad)", theta, "(0, π)",
                  "The mode is above the Nyquist frequency of the sample time; sample faster.");
  }
}

// Appends the two on-grid weights replacing amplitude A at (m + f)·Ts.
void split(std::vector<DiscreteTap>& taps, const Impulse& impulse, double sample_time_s,
           Discretization method, const Mode& mode) {
  const GridPosition at = locate(impulse.time_s, sample_time_s);
  const double a = impulse.amplitude;
  if (at.f == 0.0) {
    taps.push_back({at.m, a});
    return;
  }
  double w0 = 0.0;
  double w1 = 0.0;
  if (method == Discretization::linear) {
    // First-order hold (Vaughan's digseq): u(kTs − t) = (1−f)·u[k−m] + f·u[k−m−1].
    w0 = a * (1.0 - at.f);
    w1 = a * at.f;
  } else {
    // Murphy & Watanabe 1992: B₀ + B₁·r·e^{−jθ} = A·r^f·e^{−jfθ} with r = e^{ζωnTs}, θ = ωdTs,
    // so B₀ = A·r^f·sin((1−f)θ)/sin θ and B₁ = A·r^(f−1)·sin(fθ)/sin θ.
    const double theta = mode.damped_frequency_rad_s() * sample_time_s;
    const double log_r = mode.damping_ratio * mode.natural_frequency_rad_s * sample_time_s;
    const double sin_theta = std::sin(theta);
    w0 = a * std::exp(at.f * log_r) * std::sin((1.0 - at.f) * theta) / sin_theta;
    w1 = a * std::exp((at.f - 1.0) * log_r) * std::sin(at.f * theta) / sin_theta;
  }
  taps.push_back({at.m, w0});
  taps.push_back({at.m + 1, w1});
}

// Adds w·u[k − d] (u held at its ends) to y[k] for k in [k0, k1).
void add_tap(double* y, std::size_t k0, std::size_t k1, const DiscreteTap& tap, const double* u,
             std::size_t n) {
  const double w = tap.weight;
  const std::size_t d = tap.delay_samples;
  const std::size_t head_end = std::clamp(d, k0, k1);          // k < d: before the first sample
  const std::size_t body_end = std::clamp(n + d, head_end, k1);  // d <= k < n + d: inside
  const double before = w * u[0];
  for (std::size_t k = k0; k < head_end; ++k) y[k - k0] += before;
  for (std::size_t k = head_end; k < body_end; ++k) y[k - k0] += w * u[k - d];
  const double after = w * u[n - 1];
  for (std::size_t k = body_end; k < k1; ++k) y[k - k0] += after;
}

}  // namespace

std::vector<DiscreteTap> discretize(const Shaper& shaper, double sample_time_s,
                                    Discretization method, const Mode& mode) {
  require_positive("sample_time_s", sample_time_s);
  if (method == Discretization::exact_at_mode) validate_mode(mode, sample_time_s);
  std::vector<DiscreteTap> raw;
  raw.reserve(2 * shaper.size());
  for (const Impulse& impulse : shaper.impulses()) split(raw, impulse, sample_time_s, method, mode);

  // Impulse times increase, so delays are already sorted; merge equal delays.
  std::vector<DiscreteTap> taps;
  taps.reserve(raw.size());
  for (const DiscreteTap& tap : raw) {
    if (!taps.empty() && taps.back().delay_samples == tap.delay_samples) {
      taps.back().weight += tap.weight;
    } else {
      taps.push_back(tap);
    }
  }
  std::erase_if(taps, [](const DiscreteTap& t) { return t.weight == 0.0; });

  if (method == Discretization::exact_at_mode) {
    // Rescale to the shaper's ΣA so that a step still reaches its final value; the mode's
    // cancellation condition is homogeneous in the weights and survives the scaling.
    double sum = 0.0;
    for (const DiscreteTap& t : taps) sum += t.weight;
    if (!(std::abs(sum) > 1e-12)) {
      throw_invalid("sum of exact_at_mode weights", sum, "non-zero",
                    "The sample time is too coarse for this shaper; sample faster.");
    }
    const double scale = shaper.amplitude_sum() / sum;
    for (DiscreteTap& t : taps) t.weight *= scale;
  }
  return taps;
}

std::size_t max_delay_samples(std::span<const DiscreteTap> taps) noexcept {
  std::size_t d = 0;
  for (const DiscreteTap& t : taps) d = std::max(d, t.delay_samples);
  return d;
}

UniformSeries shape_offline(std::span<const DiscreteTap> taps, const UniformSeries& input,
                            bool extend) {
  require_positive("input.sample_time_s", input.sample_time_s);
  if (taps.empty()) {
    throw InvalidArgument("shape_offline: taps is empty; discretize() a Shaper to get them.");
  }
  UniformSeries out;
  out.start_s = input.start_s;
  out.sample_time_s = input.sample_time_s;
  const std::size_t n = input.size();
  if (n == 0) return out;
  const std::size_t length = n + (extend ? max_delay_samples(taps) : 0);
  out.values.assign(length, 0.0);
  // Blocked: every tap is added over one L1-sized block before the next block, in tap order
  // (the same summation order as StreamingShaper::step, so the two agree to the last bit
  // unless the compiler contracts differently).
  double* y = out.values.data();
  for (std::size_t k0 = 0; k0 < length; k0 += kBlock) {
    const std::size_t k1 = std::min(length, k0 + kBlock);
    for (const DiscreteTap& tap : taps) add_tap(y + k0, k0, k1, tap, input.values.data(), n);
  }
  return out;
}

UniformSeries shape_offline(const Shaper& shaper, const UniformSeries& input, bool extend) {
  require_positive("input.sample_time_s", input.sample_time_s);
  const std::vector<DiscreteTap> taps = discretize(shaper, input.sample_time_s);
  return shape_offline(taps, input, extend);
}

}  // namespace clearshape::shaping
