#include "clearshape/signal/signal.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "clearshape/core/error.hpp"
#include "clearshape/signal/prbs.hpp"
#include "time_tolerance.hpp"

namespace clearshape::signal {

namespace {

constexpr std::array<std::string_view, std::variant_size_v<SignalSpec>> kTypeNames = {
    "step", "ramp", "sine", "prbs", "double-step", "stacked-steps", "parabolic", "trapezoid", "chirp"};

// PRBS sampled bit by bit: the register steps forward as the bit index grows.
void sample_prbs(const Prbs& prbs, UniformSeries& series) {
  Lfsr lfsr(prbs.order, prbs.seed);
  double current = 0.0;  // bit index whose value is bit 0 of the register
  for (std::size_t i = 0; i < series.values.size(); ++i) {
    const double t_s = series.time_s(i);
    if (!detail::reached(t_s, prbs.start_s)) {
      series.values[i] = prbs.offset;
      continue;
    }
    const double k = std::max(0.0, detail::interval_index(t_s, prbs.start_s, prbs.bit_period_s));
    if (k - current > 64.0) {
      lfsr.jump(static_cast<std::uint64_t>(k - current));
      current = k;
    }
    while (current < k) {
      lfsr.step();
      current += 1.0;
    }
    series.values[i] = prbs.level((lfsr.state() & 1u) != 0);
  }
}

}  // namespace

Signal::Signal(SignalSpec spec) : spec_(std::move(spec)) {
  std::visit([](const auto& s) { s.validate(); }, spec_);
}

std::string_view Signal::type() const noexcept { return kTypeNames[spec_.index()]; }

double Signal::value_at(double t_s) const noexcept {
  return std::visit([t_s](const auto& s) { return s.value_at(t_s); }, spec_);
}

UniformSeries sample(const Signal& signal, double sample_rate_hz, double duration_s) {
  require_positive("sample_rate_hz", sample_rate_hz);
  require_non_negative("duration_s", duration_s);
  UniformSeries series;
  series.start_s = 0.0;
  series.sample_time_s = 1.0 / sample_rate_hz;
  series.values.resize(sample_count(duration_s, series.sample_time_s));
  if (const auto* prbs = signal.get_if<Prbs>()) {
    sample_prbs(*prbs, series);
    return series;
  }
  for (std::size_t i = 0; i < series.values.size(); ++i) {
    series.values[i] = signal.value_at(series.time_s(i));
  }
  return series;
}

}  // namespace clearshape::signal
