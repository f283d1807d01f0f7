#pragma once
// `--export klipper`: the [input_shaper] section of Klipper's printer.cfg (Klipper
// docs/Config_Reference.md: shaper_type_x/y, shaper_freq_x/y in Hz — the undamped natural
// frequency —, damping_ratio_x/y). Klipper builds the shaper itself from these three numbers
// (firmware_shapers.hpp), so only methods Klipper has are exported: zv, mzv, zvd, ei (its EI
// fixes Vtol at 5 %), ei2 → 2hump_ei, ei3 → 3hump_ei. The shaper Klipper will build from the
// printed numbers is compared with the design; a residual-vibration difference above
// kFirmwareResidualTolerance over r ∈ [0.5, 1.5] is refused. Frequencies and damping are
// written to 6 significant digits.
#include "clearshape/export/export.hpp"

namespace clearshape::exports {

/// Klipper's name for a method, or nullopt when Klipper lacks it.
std::optional<std::string_view> klipper_type_for(shaping::Method method);

ExportText to_klipper(const ShaperDesign& design, const ExportOptions& options);

}  // namespace clearshape::exports
