#include "clearshape/shaping/apply.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <utility>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::shaping {
namespace {

// A shaper longer than this many samples is a unit mistake (ms given as s), not a design.
constexpr double kMaxDelaySamples = 67108864.0;  // 2^26
// t/Ts within this relative distance of an integer is floating-point noise of the division.
constexpr double kOnGridTolerance = 1e-12;

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

// y[k] = Σ w_j·u[k − d_j] with u held at its ends, for any k. Even and odd taps are summed
// apart and then added — the order of StreamingShaper::step, so the two agree to the last bit.
double shaped_sample(std::span<const DiscreteTap> taps, const double* u, std::size_t n,
                     std::size_t k) noexcept {
  auto input_at = [&](std::size_t d) { return k < d ? u[0] : (k - d < n ? u[k - d] : u[n - 1]); };
  double even = 0.0;
  double odd = 0.0;
  std::size_t j = 0;
  for (; j + 1 < taps.size(); j += 2) {
    even += taps[j].weight * input_at(taps[j].delay_samples);
    odd += taps[j + 1].weight * input_at(taps[j + 1].delay_samples);
  }
  if (j < taps.size()) even += taps[j].weight * input_at(taps[j].delay_samples);
  return even + odd;
}

// The same for k in [k0, k1) where every u[k − d_j] exists, with N taps known at compile time
// so that the tap loop unrolls and the k loop vectorises (same summation order).
template <std::size_t N>
void shape_interior(std::span<const DiscreteTap> taps, const double* u, double* y, std::size_t k0,
                    std::size_t k1) noexcept {
  std::array<double, N> w{};
  std::array<std::size_t, N> d{};
  for (std::size_t j = 0; j < N; ++j) {
    w[j] = taps[j].weight;
    d[j] = taps[j].delay_samples;
  }
  for (std::size_t k = k0; k < k1; ++k) {
    double even = 0.0;
    double odd = 0.0;
    for (std::size_t j = 0; j < N; j += 2) {
      even += w[j] * u[k - d[j]];
      if (j + 1 < N) odd += w[j + 1] * u[k - d[j + 1]];
    }
    y[k] = even + odd;
  }
}

using InteriorKernel = void (*)(std::span<const DiscreteTap>, const double*, double*, std::size_t,
                                std::size_t) noexcept;

// Kernels for 1…kMaxFixedTaps taps (a 5-impulse shaper split linearly has at most 10).
constexpr std::size_t kMaxFixedTaps = 16;
template <std::size_t... I>
constexpr std::array<InteriorKernel, sizeof...(I)> make_kernels(std::index_sequence<I...>) {
  return {&shape_interior<I + 1>...};
}
constexpr auto kKernels = make_kernels(std::make_index_sequence<kMaxFixedTaps>{});

}  // namespace

std::vector<DiscreteTap> discretize(const Shaper& shaper, double sample_time_s,
                                    Discretization method, const Mode& mode) {
  require_positive("sample_time_s", sample_time_s);
  if (method == Discretization::exact_at_mode) validate_mode(mode, sample_time_s);
  std::vector<DiscreteTap> raw;
  raw.reserve(2 * shaper.size());
  for (const Impulse& impulse : shaper.impulses()) split(raw, impulse, sample_time_s, method, mode);

  // An impulse's second tap (m+1) can precede the next impulse's first (m) when several impulses
  // fall within one sample (a shaper shorter than Ts): sort by delay, then merge equal delays.
  std::stable_sort(raw.begin(), raw.end(),
                   [](const DiscreteTap& a, const DiscreteTap& b) { return a.delay_samples < b.delay_samples; });
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
  out.values.resize(length);
  const double* u = input.values.data();
  double* y = out.values.data();
  // Interior [D, n): all taps inside the input; before and after it the input is held.
  const std::size_t interior_begin = std::min(max_delay_samples(taps), n);
  const std::size_t interior_end = std::max(interior_begin, n);
  for (std::size_t k = 0; k < interior_begin; ++k) y[k] = shaped_sample(taps, u, n, k);
  if (taps.size() <= kMaxFixedTaps) {
    kKernels[taps.size() - 1](taps, u, y, interior_begin, interior_end);
  } else {
    for (std::size_t k = interior_begin; k < interior_end; ++k) y[k] = shaped_sample(taps, u, n, k);
  }
  for (std::size_t k = interior_end; k < length; ++k) y[k] = shaped_sample(taps, u, n, k);
  return out;
}

UniformSeries shape_offline(const Shaper& shaper, const UniformSeries& input, bool extend) {
  require_positive("input.sample_time_s", input.sample_time_s);
  const std::vector<DiscreteTap> taps = discretize(shaper, input.sample_time_s);
  return shape_offline(taps, input, extend);
}

}  // namespace clearshape::shaping
