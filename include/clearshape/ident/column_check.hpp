#pragma once
// Whether an input/output pair can identify anything: an output that is the input passed through
// a D/A converter or a pulse train — the same values up to its quantisation, apart from short runs
// while a new value waits for the next update — has no dynamics to identify (issue 20: `identify`
// on a recording's command and applied-command columns fitted a 410 Hz, ζ ≈ 0 "model" of the D/A).
#include <cstddef>
#include <span>

namespace clearshape::ident {

/// The quantisation a converted copy may add: 1 % of the input's range (coarser than a 12-bit
/// converter's step, 0.024 %, and the thesis's 0.12° pulse on a 20° step, 0.6 %).
inline constexpr double kCopyTolerance = 0.01;

/// True when |output − input| ≤ kCopyTolerance × the input's range at every sample except in runs
/// of at most `max_hold_samples` (the converter's update hold) that start within that hold after
/// a change of the input, and the input moves at all. A drive's response keeps differing from its
/// command for longer than a hold after a change. Sizes must match.
bool is_converted_copy(std::span<const double> input, std::span<const double> output, std::size_t max_hold_samples);

}  // namespace clearshape::ident
