#pragma once
// Shaper-design options shared by `clearshape shape` and `clearshape sensitivity`
// (implemented in cmd_shape.cpp).
#include <optional>
#include <string>
#include <string_view>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"

namespace clearshape::cli {

struct ShaperOptions {
  std::string method;
  double frequency_hz = 0.0;
  double wn_rad_s = 0.0;
  double zeta = 0.0;
  double vtol = 0.05;
  double band_low_hz = 0.0;
  double band_high_hz = 0.0;
  int si_impulses = 0;
  int si_points = 60;
  std::string impulses;
  double second_frequency_hz = 0.0;
  double second_zeta = 0.0;
  CLI::Option* frequency_option = nullptr;
  CLI::Option* wn_option = nullptr;
  CLI::Option* zeta_option = nullptr;
  CLI::Option* band_low_option = nullptr;
  CLI::Option* band_high_option = nullptr;
  CLI::Option* impulses_option = nullptr;
  CLI::Option* second_frequency_option = nullptr;
  CLI::Option* second_zeta_option = nullptr;
};

/// Adds --method, --frequency-hz/--wn, --zeta, --vtol, --band-low-hz/--band-high-hz,
/// --si-impulses, --si-points, --impulses, --second-frequency-hz/--second-zeta.
void add_shaper_options(CLI::App& sub, ShaperOptions& options);

struct DesignedShaper {
  shaping::Shaper shaper;
  std::optional<shaping::Mode> mode;  ///< the design mode (absent for custom without a mode)
  std::optional<shaping::Mode> second_mode;
};

/// Validates the options (InvalidArgument naming the option, value and allowed range) and
/// designs the shaper. Prints the negative-impulse warning on stderr for um-zv and negative
/// custom shapers. `command` prefixes messages.
DesignedShaper design_from_options(const ShaperOptions& options, std::string_view command);

/// {"frequency_hz", "natural_frequency_rad_s", "zeta"}.
nlohmann::ordered_json mode_json(const shaping::Mode& mode);
/// The V <= vtol band as JSON: vtol, width, ratio_low/high, frequency_low/high_hz.
nlohmann::ordered_json band_json(const shaping::InsensitivityBand& band, const shaping::Mode& mode,
                                 double vtol);

}  // namespace clearshape::cli
