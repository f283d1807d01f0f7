#include "clearshape/shaping/streaming.hpp"

#include <bit>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::shaping {
namespace {

constexpr std::size_t kMaxDelaySamples = std::size_t{1} << 26;  // same limit as discretize()

std::vector<DiscreteTap> checked_taps(std::span<const DiscreteTap> taps) {
  if (taps.empty()) {
    throw InvalidArgument("StreamingShaper: taps is empty; discretize() a Shaper to get them.");
  }
  for (std::size_t j = 0; j < taps.size(); ++j) {
    if (!std::isfinite(taps[j].weight)) {
      throw InvalidArgument(fmt::format("StreamingShaper: tap {} weight = {} is not finite", j + 1,
                                        taps[j].weight));
    }
    if (taps[j].delay_samples > kMaxDelaySamples) {
      throw InvalidArgument(fmt::format(
          "StreamingShaper: tap {} delay = {} samples is out of range; allowed: <= 2^26. Check the "
          "units of the sample time.", j + 1, taps[j].delay_samples));
    }
  }
  return {taps.begin(), taps.end()};
}

}  // namespace

StreamingShaper::StreamingShaper(const Shaper& shaper, double sample_time_s, double initial_value)
    : StreamingShaper(discretize(shaper, sample_time_s), sample_time_s, initial_value) {}

StreamingShaper::StreamingShaper(std::span<const DiscreteTap> taps, double sample_time_s,
                                 double initial_value)
    : taps_(checked_taps(taps)), sample_time_s_(sample_time_s) {
  require_positive("sample_time_s", sample_time_s);
  require_finite("initial_value", initial_value);
  // The newest sample plus max-delay older ones, rounded up to a power of two for masking.
  history_.assign(std::bit_ceil(max_delay_samples(taps_) + 1), initial_value);
  mask_ = history_.size() - 1;
  head_ = 0;
}

Status StreamingShaper::step(double input, double& output) noexcept {
  Status status = Status::ok;
  if (!std::isfinite(input)) {
    input = history_[head_];  // hold the previous input
    status = Status::not_finite;
  }
  head_ = (head_ + 1) & mask_;
  history_[head_] = input;
  // y[k] = Σ w_j·u[k − d_j] (the FIR of discretize()); unsigned wrap-around then mask. Even and
  // odd taps go to two accumulators (half the dependent-add chain), the order shape_offline uses.
  const double* h = history_.data();
  const DiscreteTap* tap = taps_.data();
  const std::size_t n = taps_.size();
  double even = 0.0;
  double odd = 0.0;
  std::size_t j = 0;
  for (; j + 1 < n; j += 2) {
    even += tap[j].weight * h[(head_ - tap[j].delay_samples) & mask_];
    odd += tap[j + 1].weight * h[(head_ - tap[j + 1].delay_samples) & mask_];
  }
  if (j < n) even += tap[j].weight * h[(head_ - tap[j].delay_samples) & mask_];
  output = even + odd;
  return status;
}

double StreamingShaper::step(double input) noexcept {
  double output = 0.0;
  step(input, output);
  return output;
}

void StreamingShaper::reset(double value) noexcept {
  for (double& h : history_) h = value;
  head_ = 0;
}

}  // namespace clearshape::shaping
