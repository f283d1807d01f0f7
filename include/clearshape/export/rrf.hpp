#pragma once
// `--export rrf`: one M593 line for RepRapFirmware 3.5/3.6 (Duet3D G-code dictionary, M593
// "Configure Input Shaping"; src/Movement/AxisShaper.cpp): P"type" F<Hz> S<ζ> for the named
// types RRF designs itself (zvd, zvdd, zvddd, mzv, ei2, ei3), or P"custom" H<cumulative
// amplitudes> T<durations, s> — RRF's form for any positive shaper of at most 5 impulses.
// A named type is written only when the shaper RRF builds from the printed numbers matches the
// design within kFirmwareResidualTolerance; otherwise (zv, ei, si, a two-mode convolution,
// RRF's reversed MZV at ζ > 0, …) the custom form carries the design itself. Refused: negative
// shapers, more than 5 impulses, and F outside RRF's range for a named type. Numbers: 6
// significant digits (RRF stores them as binary32).
#include "clearshape/export/export.hpp"

namespace clearshape::exports {

/// RRF's name for a method, or nullopt when RRF has no named type for it.
std::optional<std::string_view> rrf_type_for(shaping::Method method);

/// RRF accepts F in [StepClockRate/131070, 1000] Hz (a 16-bit half period in step clocks):
/// 750 kHz step clock (Duet 3) → 5.722 Hz.
inline constexpr double kRrfMinFrequencyHz = 750000.0 / 131070.0;
inline constexpr double kRrfMaxFrequencyHz = 1000.0;
inline constexpr std::size_t kRrfMaxImpulses = 5;

ExportText to_rrf(const ShaperDesign& design, const ExportOptions& options);

}  // namespace clearshape::exports
