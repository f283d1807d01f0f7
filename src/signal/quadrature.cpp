#include "clearshape/signal/quadrature.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::signal {

namespace {

// Position in the forward Gray sequence 00 → 10 → 11 → 01 of levels (A, B).
int gray_index(bool a, bool b) noexcept { return a ? (b ? 2 : 1) : (b ? 3 : 0); }

struct Levels {
  bool a;
  bool b;
};
// Levels after `done` edges of whole pulses started from 00.
Levels levels_after(std::int64_t done, bool forward) noexcept {
  static constexpr Levels kForward[4] = {{false, false}, {true, false}, {true, true}, {false, true}};
  static constexpr Levels kReverse[4] = {{false, false}, {false, true}, {true, true}, {true, false}};
  const auto e = static_cast<std::size_t>(done % 4);
  return forward ? kForward[e] : kReverse[e];
}

// Edge number q (0-based) of a period: which channel changes and its new level.
QuadratureEdge edge_of(std::int64_t q, bool forward, double time_s) noexcept {
  const Levels before = levels_after(q, forward);
  const Levels after = levels_after(q + 1, forward);
  if (before.a != after.a) return {time_s, Channel::a, after.a};
  return {time_s, Channel::b, after.b};
}

}  // namespace

QuadratureTrace quadrature_trace(const PositionPathResult& path, double from_s, double to_s,
                                 std::size_t max_edges) {
  require_finite("from_s", from_s);
  require_finite("to_s", to_s);
  if (!(to_s > from_s)) {
    throw_invalid("to_s", to_s, fmt::format("> from_s = {}", from_s));
  }
  const double period_s = path.update_period_s();
  const double start_s = path.update_start_s();
  const std::size_t updates = path.pulses_per_update.size();

  // Edge q of period k falls at t_k + (q + 1)·T/(4|N|); edges_before(k, t) counts those < t.
  const auto edges_before = [&](std::size_t k, double t_s) -> std::int64_t {
    const std::int64_t n = std::abs(path.pulses_per_update[k]);
    const double t_k = start_s + static_cast<double>(k) * period_s;
    const double step_s = period_s / static_cast<double>(4 * n);
    auto q = static_cast<std::int64_t>(std::clamp(std::ceil((t_s - t_k) / step_s) - 1.0, 0.0,
                                                  static_cast<double>(4 * n)));
    while (q > 0 && t_k + static_cast<double>(q) * step_s >= t_s) --q;       // edge q−1 not before t
    while (q < 4 * n && t_k + static_cast<double>(q + 1) * step_s < t_s) ++q; // edge q before t
    return q;
  };

  QuadratureTrace trace;
  std::int64_t count = path.initial_count;
  std::size_t total = 0;
  bool state_set = false;
  for (std::size_t k = 0; k < updates; ++k) {
    const std::int64_t pulses = path.pulses_per_update[k];
    const double t_k = start_s + static_cast<double>(k) * period_s;
    if (pulses == 0) {
      if (!state_set && from_s < t_k + period_s) {
        trace.start_edges = 4 * count;
        state_set = true;
      }
      continue;
    }
    const bool forward = pulses > 0;
    const std::int64_t lo = edges_before(k, from_s);
    const std::int64_t hi = edges_before(k, to_s);
    if (!state_set && lo < 4 * std::abs(pulses)) {
      const Levels l = levels_after(lo, forward);
      trace.a_high = l.a;
      trace.b_high = l.b;
      trace.start_edges = 4 * count + (forward ? lo : -lo);
      state_set = true;
    }
    if (hi > lo) {
      total += static_cast<std::size_t>(hi - lo);
      if (total > max_edges) {
        throw_invalid("quadrature window edges", static_cast<double>(total),
                      fmt::format("<= {}", max_edges), "Narrow the window [from_s, to_s)");
      }
      const double step_s = period_s / static_cast<double>(4 * std::abs(pulses));
      for (std::int64_t q = lo; q < hi; ++q) {
        trace.edges.push_back(edge_of(q, forward, t_k + static_cast<double>(q + 1) * step_s));
      }
    }
    count += pulses;
  }
  if (!state_set) trace.start_edges = 4 * count;  // window after the last pulse
  return trace;
}

Status QuadratureDecoder::apply(const QuadratureEdge& edge) noexcept {
  bool a = a_;
  bool b = b_;
  if (edge.channel == Channel::a) {
    if (edge.high == a_) return Status::out_of_range;
    a = edge.high;
  } else {
    if (edge.high == b_) return Status::out_of_range;
    b = edge.high;
  }
  // ×4 decoding: one step forward or back along the Gray sequence per edge.
  const int delta = (gray_index(a, b) - gray_index(a_, b_) + 4) % 4;
  count_ += delta == 1 ? 1 : -1;
  a_ = a;
  b_ = b;
  return Status::ok;
}

}  // namespace clearshape::signal
