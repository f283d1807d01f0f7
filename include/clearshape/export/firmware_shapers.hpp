#pragma once
// The shapers two printer firmwares build from a type name, a frequency and a damping ratio —
// written here from their published definitions so an export can be checked against what the
// firmware will actually run (not against what we hope it runs).
//   Klipper (klippy/extras/shaper_defs.py; docs/Config_Reference.md [input_shaper]):
//     zv, mzv, zvd: the ZV family and MZV on the damped period Td = 1/(f·√(1−ζ²));
//     ei: Singhose's damped EI curve fit at Vtol = 5 % (SHAPER_VIBRATION_REDUCTION = 20);
//     2hump_ei, 3hump_ei: Singhose's damped curve fits at Vtol = 5 %, times on the UNDAMPED
//     period 1/f. f is the undamped natural frequency (shaper_freq_*), ζ = damping_ratio_*.
//   RepRapFirmware 3.5/3.6 (M593, src/Movement/AxisShaper.cpp):
//     zvd, zvdd, zvddd: the ZV family on the damped period;
//     mzv: Klipper's MZV amplitudes in REVERSED order (the K²-scaled one first) — equal to
//     ours only at ζ = 0;
//     ei2, ei3: the same curve fits as Klipper's 2hump/3hump, times on the DAMPED period;
//     custom: H = cumulative amplitudes of every impulse but the last, T = durations between
//     impulses (s); at most 4 extra impulses (5 in all).
// Amplitudes are normalised to ΣA = 1 (both firmwares normalise).
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "clearshape/shaping/shaper.hpp"

namespace clearshape::exports {

/// Klipper's shaper type names: zv, mzv, zvd, ei, 2hump_ei, 3hump_ei.
std::vector<std::string_view> klipper_types();
/// RRF's M593 named types with a design (custom excluded): mzv, zvd, zvdd, zvddd, ei2, ei3.
std::vector<std::string_view> rrf_types();

/// The shaper Klipper builds; nullopt for an unknown type. f > 0, ζ in [0, 1).
std::optional<shaping::Shaper> klipper_shaper(std::string_view type, double frequency_hz, double zeta);
/// The shaper RRF builds for a named type; nullopt for an unknown type.
std::optional<shaping::Shaper> rrf_shaper(std::string_view type, double frequency_hz, double zeta);

/// RRF's custom form: impulses from H (cumulative amplitudes) and T (durations, s).
/// Throws InvalidArgument when the sizes differ or a duration is not > 0.
shaping::Shaper rrf_custom_shaper(const std::vector<double>& h, const std::vector<double>& t_s);

/// How far apart two shapers' residual vibration curves are for a mode: max over r = ω/ωn in
/// [ratio_low, ratio_high] (`points` evenly spaced) of |V_a(r·ωn, ζ) − V_b(r·ωn, ζ)|.
struct ResidualDifference {
  double max_abs = 0.0;
  double at_ratio = 1.0;
};
ResidualDifference residual_difference(const shaping::Shaper& a, const shaping::Shaper& b,
                                       const shaping::Mode& mode, double ratio_low = 0.5,
                                       double ratio_high = 1.5, std::size_t points = 401);

/// The tolerance an export to a firmware's named type must meet: the firmware's shaper and the
/// design may differ in V by at most 0.01 (1 % of the unshaped vibration) anywhere in r ∈ [0.5, 1.5].
inline constexpr double kFirmwareResidualTolerance = 0.01;

}  // namespace clearshape::exports
