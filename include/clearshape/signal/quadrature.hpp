#pragma once
// The A/B quadrature pulse train of the position-mode path as edge events, and a ×4 decoder.
// One command pulse is a full A/B cycle of four edges. Forward (A leads B), levels (A, B) go
// 00 → 10 → 11 → 01 → 00; reverse goes 00 → 01 → 11 → 10 → 00 (thesis Fig. 3.5–3.6, input
// pulse logic "0": A phase + B phase). In a period carrying N pulses at frequency f = N/T the
// edges of pulse j fall at t_k + (j + (e + 1)/4)/|f|, e = 0 … 3.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "clearshape/core/status.hpp"
#include "clearshape/signal/position_path.hpp"

namespace clearshape::signal {

enum class Channel : std::uint8_t { a, b };

struct QuadratureEdge {
  double time_s = 0.0;
  Channel channel = Channel::a;
  bool high = false;  ///< the channel's level after the edge
};

/// The edges in a time window and the state just before it.
struct QuadratureTrace {
  bool a_high = false;             ///< levels at from_s (before any edge at from_s)
  bool b_high = false;
  std::int64_t start_edges = 0;    ///< ×4 count (4·initial count + edges so far) at from_s
  std::vector<QuadratureEdge> edges;  ///< time-ordered, from_s <= time_s < to_s
};

/// The quadrature edges of `path` with from_s <= time < to_s. Throws InvalidArgument when the
/// window is empty or reversed or holds more than `max_edges` edges (narrow the window).
QuadratureTrace quadrature_trace(const PositionPathResult& path, double from_s, double to_s,
                                 std::size_t max_edges = 1'000'000);

/// ×4 quadrature decoder: ±1 per valid Gray-code transition.
class QuadratureDecoder {
 public:
  QuadratureDecoder(bool a_high, bool b_high, std::int64_t count) noexcept
      : a_(a_high), b_(b_high), count_(count) {}
  /// Applies one edge. Returns Status::out_of_range (count unchanged) when the edge does not
  /// change the channel's level.
  Status apply(const QuadratureEdge& edge) noexcept;
  std::int64_t count() const noexcept { return count_; }
  bool a_high() const noexcept { return a_; }
  bool b_high() const noexcept { return b_; }

 private:
  bool a_;
  bool b_;
  std::int64_t count_;
};

}  // namespace clearshape::signal
