#include "clearshape/export/klipper.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/version.hpp"
#include "clearshape/export/firmware_shapers.hpp"
#include "clearshape/export/numbers.hpp"

namespace clearshape::exports {

namespace sh = clearshape::shaping;

namespace {

constexpr int kDigits = 6;  // significant digits of shaper_freq and damping_ratio
constexpr double kKlipperVtol = 0.05;  // Klipper's EI family: SHAPER_VIBRATION_REDUCTION = 20

std::string instead(sh::Method m) {
  switch (m) {
    case sh::Method::zvdd:
    case sh::Method::zvddd:
      return "zvd (shorter, less robust) or ei / ei2 (Klipper's ei / 2hump_ei: wider bands), or --export rrf "
             "(RRF has zvdd and zvddd) or c-header / json";
    case sh::Method::si:
      return "ei, ei2 or ei3 (Klipper's ei / 2hump_ei / 3hump_ei) whose band is closest to yours, or --export "
             "c-header / json / rrf (custom) for the SI shaper itself";
    case sh::Method::um_zv:
      return "zv or mzv (positive shapers: a negative one reverses the command, bad for a joint with clearance)";
    case sh::Method::custom:
      return "--export rrf (its custom form takes impulses) or c-header / json";
    default:
      return "--export c-header or json";
  }
}

}  // namespace

std::optional<std::string_view> klipper_type_for(sh::Method method) {
  switch (method) {
    case sh::Method::zv: return "zv";
    case sh::Method::mzv: return "mzv";
    case sh::Method::zvd: return "zvd";
    case sh::Method::ei: return "ei";
    case sh::Method::ei2: return "2hump_ei";
    case sh::Method::ei3: return "3hump_ei";
    default: return std::nullopt;
  }
}

ExportText to_klipper(const ShaperDesign& design, const ExportOptions& options) {
  const std::string& axes = options.klipper_axes;
  if (axes != "x" && axes != "y" && axes != "xy") {
    throw InvalidArgument(fmt::format("--export-axis = '{}' is not valid; allowed: x, y, xy", axes));
  }
  const std::optional<std::string_view> type = klipper_type_for(design.method);
  if (!type) {
    throw InvalidArgument(fmt::format("--export klipper: Klipper has no {} shaper (its types: {}); use {}",
                                      sh::to_string(design.method), fmt::join(klipper_types(), ", "), instead(design.method)));
  }
  if (design.second_mode) {
    throw InvalidArgument("--export klipper: Klipper shapes one mode per axis (no convolution of two shapers); export "
                          "the two-mode shaper with --export c-header, json or rrf (custom), or give Klipper the "
                          "dominant mode alone");
  }
  if (!design.mode) throw InvalidArgument("--export klipper needs the mode (--frequency-hz and --zeta)");
  if (design.vtol && std::abs(*design.vtol - kKlipperVtol) > 1e-12) {
    throw InvalidArgument(fmt::format("--export klipper: Klipper's {} fixes the tolerable vibration at 5 %, the design "
                                      "has --vtol {}; design with --vtol 0.05, or export this one with --export "
                                      "c-header or json", *type, *design.vtol));
  }
  const std::string freq = fixed_significant(design.mode->natural_frequency_hz(), kDigits);
  const std::string zeta = fixed_significant(design.mode->damping_ratio, kDigits);
  // What Klipper will build from the numbers as printed, against the design.
  const std::optional<sh::Shaper> theirs = klipper_shaper(*type, std::stod(freq), std::stod(zeta));
  const ResidualDifference diff = residual_difference(design.shaper, *theirs, *design.mode);
  if (diff.max_abs > kFirmwareResidualTolerance && design.update_grid_hz) {
    throw InvalidArgument(fmt::format(
        "--export klipper: the {} Klipper builds from {} Hz, damping {} is not the design on the {} Hz update grid: residual "
        "vibration differs by {:.3g} at r = {:.3g} (tolerance {} over r = 0.5 … 1.5); Klipper places impulses itself. Export "
        "the grid shaper with --export c-header, json or rrf (custom form)",
        *type, freq, zeta, fixed_significant(*design.update_grid_hz, kDigits), diff.max_abs, diff.at_ratio, kFirmwareResidualTolerance));
  }
  if (diff.max_abs > kFirmwareResidualTolerance) {
    throw InvalidArgument(fmt::format(
        "--export klipper: the {} Klipper builds from {} Hz, damping {} differs from the designed {}: residual "
        "vibration differs by {:.3g} at r = {:.3g} (tolerance {} over r = 0.5 … 1.5); Klipper's EI-family fits hold for "
        "small damping (ei up to ζ ≈ 0.4, 2hump_ei 0.3, 3hump_ei 0.2). Export with --export c-header, json or rrf",
        *type, freq, zeta, sh::to_string(design.method), diff.max_abs, diff.at_ratio, kFirmwareResidualTolerance));
  }
  std::string s;
  s += fmt::format("# Input shaper exported by clearshape {} for Klipper's printer.cfg.\n", kVersion);
  if (!design.command.empty()) s += fmt::format("#   {}\n", design.command);
  s += fmt::format("# Klipper builds {} itself from shaper_freq (the undamped natural frequency, Hz) and damping_ratio\n"
                   "# (klippy/extras/shaper_defs.py). Its shaper and the design differ in residual vibration by at most\n"
                   "# {:.2g} over 0.5 .. 1.5 x {} Hz (tolerance {}).\n",
                   *type, diff.max_abs, freq, kFirmwareResidualTolerance);
  if (design.update_grid_hz) {
    s += fmt::format("# The design compared is the one on the drive's {} Hz update grid.\n", fixed_significant(*design.update_grid_hz, kDigits));
  }
  s += "[input_shaper]\n";
  for (char axis : axes) {
    s += fmt::format("shaper_type_{}: {}\n", axis, *type);
    s += fmt::format("shaper_freq_{}: {}\n", axis, freq);
    s += fmt::format("damping_ratio_{}: {}\n", axis, zeta);
  }
  return {s, {}};
}

}  // namespace clearshape::exports
