#pragma once
// Running a second-order-section filter: causally one sample at a time (real time), causally
// over a whole signal (scipy.signal.sosfilt), and forward-backward with zero phase
// (scipy.signal.sosfiltfilt). Each section is a transposed direct form II with the same
// operations in the same order as scipy's sosfilt (bitwise-equal outputs in bench/dsp_peer.py);
// offline, 1–8 sections run a register-resident kernel, more run in blocks per section.
#include <array>
#include <cstddef>
#include <optional>
#include <span>
#include <vector>

#include "clearshape/core/status.hpp"
#include "clearshape/dsp/sos.hpp"

namespace clearshape::dsp {

/// Two delay states per section, scipy's `zi`/`zf` layout (n_sections × 2).
using SectionState = std::array<double, 2>;

/// Steady-state initial conditions for a unit step, per section (scipy.signal.sosfilt_zi):
/// starting from `value · sosfilt_zi(d)` the output of a constant input `value` is constant.
std::vector<SectionState> sosfilt_zi(const SosDesign& design);

/// The real-time filter: coefficients and state preallocated at construction; step() is
/// noexcept and allocation-free.
class StreamingSosFilter {
 public:
  /// Starts at rest (zero state). Allocates once.
  explicit StreamingSosFilter(const SosDesign& design);

  /// One sample in, one out. The trusted fast path: no checks.
  double step(double input) noexcept;
  /// Checked form: a non-finite input leaves the state untouched, repeats the previous output
  /// and returns Status::not_finite.
  Status step(double input, double& output) noexcept;

  /// Zero state (the input and output rested at 0).
  void reset() noexcept;
  /// Steady state for an input that has rested at `input` forever (scipy zi · input): the next
  /// output for that input is dc_gain · input, with no transient.
  void reset_steady_state(double input) noexcept;
  /// Sets the state from scipy-layout values. Throws InvalidArgument on a size mismatch.
  void set_state(std::span<const SectionState> state);
  std::span<const SectionState> state() const noexcept { return state_; }

  const SosDesign& design() const noexcept { return design_; }
  double last_output() const noexcept { return last_output_; }

 private:
  SosDesign design_;
  std::vector<SectionState> state_;
  std::vector<SectionState> unit_steady_state_;  // sosfilt_zi(design_)
  double last_output_ = 0.0;
};

/// Causal filtering from rest (scipy.signal.sosfilt(sos, x)).
std::vector<double> sosfilt(const SosDesign& design, std::span<const double> input);
/// Causal filtering from the initial state `state` (scipy sosfilt(sos, x, zi=state)); `state`
/// is updated to the final state (scipy's zf). Throws InvalidArgument on a size mismatch.
std::vector<double> sosfilt(const SosDesign& design, std::span<const double> input,
                            std::vector<SectionState>& state);

/// Edge extension before forward-backward filtering (scipy padtype).
enum class PadType { odd, even, constant, none };

struct FiltfiltOptions {
  PadType pad_type = PadType::odd;
  /// Samples added at each end. Default (nullopt) = scipy's rule
  /// 3 · (2·n_sections + 1 − min(#(b2 == 0), #(a2 == 0))).
  std::optional<std::size_t> pad_length;
};

/// The pad length sosfiltfilt uses for `design` by default (see FiltfiltOptions).
std::size_t default_pad_length(const SosDesign& design) noexcept;

/// Zero-phase forward-backward filtering, as scipy.signal.sosfiltfilt(sos, x, padtype, padlen):
/// extend the ends, filter forward from the steady state of the first sample, filter backward
/// from the steady state of the last output, drop the extension. The magnitude response is
/// |H|², the phase is zero. Throws InvalidArgument if the input is not longer than the pad
/// length (as scipy) — shorten pad_length or give a longer signal.
std::vector<double> sosfiltfilt(const SosDesign& design, std::span<const double> input,
                                const FiltfiltOptions& options = {});

}  // namespace clearshape::dsp
