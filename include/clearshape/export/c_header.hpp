#pragma once
// `--export c-header`: a self-contained C99 header for an MCU or PLC (no allocation, no
// library beyond <stdint.h> and <math.h>): the taps as double, float, Q15 and Q31 and one
// streaming shaper per type — a state struct holding a ring buffer sized at compile time, a
// reset and a step function. The double step does the arithmetic of
// shaping::StreamingShaper::step in the same order (two accumulators, even and odd taps, then
// their sum), so on an IEEE-754 binary64 target without FMA contraction (ISO C modes of GCC
// use -ffp-contract=off) it reproduces the C++ output bit for bit.
// Error bounds written into the header, with |x| <= X the input magnitude (derived in
// docs/export.md; u = 2^-24 for binary32, m = ceil(N/2) + 1 roundings on the longest chain):
//   float: |y_f − y| <= X·(Σ|w_f,j − w_j| + γ_m·Σ|w_f,j|),  γ_m = m·u/(1 − m·u)
//   Q15/Q31: |y_q − y| <= 0.5 + X·Σ|q_j/2^n − w_j|   (in LSB of the integer signal; the
//   integer accumulation is exact, the final rounding is half away from zero)
#include "clearshape/export/export.hpp"
#include "clearshape/export/fixed_point.hpp"

namespace clearshape::exports {

/// The bounds above for given taps (for tests and the header comment).
struct CHeaderBounds {
  double float_gain_error = 0.0;  ///< Σ|w_f − w| + γ_m·Σ|w_f|: multiply by X
  FixedPointTaps q15;
  FixedPointTaps q31;
};
CHeaderBounds c_header_bounds(std::span<const shaping::DiscreteTap> taps);

/// Throws InvalidArgument when options.c_name is not a C identifier.
ExportText to_c_header(const ShaperDesign& design, const ExportOptions& options);

}  // namespace clearshape::exports
