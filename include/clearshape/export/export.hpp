#pragma once
// Export a designed shaper in a form a controller loads (docs/export.md):
//   json      impulses, taps on the controller's sample grid and the residual vibration they leave
//   c-header  a self-contained C99 header: taps (double, float, Q15, Q31) and an allocation-free
//             streaming shaper per type (c_header.hpp)
//   klipper   [input_shaper] lines, when Klipper has the method (klipper.hpp)
//   rrf       an M593 line for RepRapFirmware 3.5/3.6 (rrf.hpp)
//
//   exports::ShaperDesign d{shaper, shaping::Method::zvd, mode};
//   exports::ExportOptions o; o.sample_time_s = 1e-3;
//   exports::ExportText out = exports::export_shaper(d, exports::Format::c_header, o);
//   io::write_text_atomic("shaper.h", out.text);    // out.notes: one line each, for stderr
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "clearshape/shaping/apply.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::exports {

enum class Format { json, c_header, klipper, rrf };

std::string_view to_string(Format format) noexcept;
/// "json", "c-header", "klipper", "rrf"; throws InvalidArgument listing them otherwise.
Format format_from_string(std::string_view name);
std::vector<std::string_view> format_names();

/// What was designed, as the user asked for it.
struct ShaperDesign {
  shaping::Shaper shaper;
  shaping::Method method = shaping::Method::custom;  ///< for a two-mode convolution: each factor's method
  std::optional<shaping::Mode> mode;                 ///< the design mode (absent for custom without one)
  std::optional<shaping::Mode> second_mode;          ///< set for a two-mode convolution
  std::optional<double> vtol;                        ///< ei/ei2/ei3/si
  std::optional<std::pair<double, double>> band_hz;  ///< si: the band where V <= vtol
  std::string command;                               ///< the command line that regenerates it (comments)
  /// Set when `shaper` is the design on a drive's update grid of this rate (shaping::on_update_grid):
  /// json and c-header say so; klipper and rrf compare their firmware's shaper with it.
  std::optional<double> update_grid_hz = std::nullopt;
};

struct ExportOptions {
  double sample_time_s = 0.0;  ///< json, c-header: the controller's sample time (> 0)
  shaping::Discretization discretization = shaping::Discretization::linear;
  std::string c_name = "cs_shaper";  ///< c-header: prefix of every identifier (a C identifier)
  std::string klipper_axes = "xy";   ///< klipper: x, y or xy
};

struct ExportText {
  std::string text;                ///< the file's content
  std::vector<std::string> notes;  ///< warnings and remarks, one line each (for stderr)
};

/// Throws InvalidArgument (bad option, or a method the target cannot represent — the message
/// says what to use instead).
ExportText export_shaper(const ShaperDesign& design, Format format, const ExportOptions& options);

/// The taps on the sample grid (validates the sample time; exact_at_mode needs the mode).
std::vector<shaping::DiscreteTap> export_taps(const ShaperDesign& design, const ExportOptions& options);
/// The discretised shaper as impulses at d_j·Ts with weights w_j (unnormalised), for V.
shaping::Shaper taps_as_shaper(std::span<const shaping::DiscreteTap> taps, double sample_time_s);

/// Band for the residual-vibration table of json and c-header: r = ω/ωn in [0.9, 1.1], 21 points.
inline constexpr double kBandRatioLow = 0.9;
inline constexpr double kBandRatioHigh = 1.1;
inline constexpr std::size_t kBandPoints = 21;

}  // namespace clearshape::exports
