#pragma once
// The vibration spectrum `clearshape recommend` works on, read from one recording:
//   * a clearshape CSV (any table io::read_table reads; time column by io/time_column.hpp),
//   * Klipper's raw accelerometer CSV ("#time,accel_x,accel_y,accel_z"),
//   * Klipper's PSD CSV ("freq,psd_x,psd_y,psd_z,psd_xyz", optionally followed by its shaper
//     columns, which are ignored).
// Time records become a one-sided Welch PSD (Hann, 50 % overlap, constant detrend, density
// scaling, zero-padded 4×); PSD files are taken as written. Errors name file, line and field.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "clearshape/core/series.hpp"

namespace clearshape::advise {

enum class InputFormat { table, klipper_raw, klipper_psd };
std::string_view to_string(InputFormat format) noexcept;

/// The format of a file's text, from its first non-blank line: "#time," → Klipper raw,
/// "freq,psd_x" → Klipper PSD, anything else → a clearshape table.
InputFormat detect_format(std::string_view text) noexcept;

/// One axis of a Klipper file on the spectrum's frequency grid.
struct AxisSpectrum {
  std::string column;          ///< "psd_x", "psd_y", "psd_z", "psd_xyz" (raw files: accel_x … xyz)
  std::vector<double> power;
};

struct MeasuredSpectrum {
  std::string source;             ///< file name (for messages and the JSON)
  InputFormat format = InputFormat::table;
  std::string column;             ///< what was analysed ("gyro_deg_s", "accel_x", "psd_xyz", …)
  std::vector<double> frequency_hz;
  std::vector<double> power;      ///< one-sided PSD, in power_unit
  /// The PSD's unit: Klipper's accelerations give (mm/s²)²/Hz; a table's column the square of the
  /// unit its name's suffix declares (psd_unit_of_column).
  std::string power_unit;
  /// Klipper files: every axis's PSD and their sum (x, y, z, xyz, as Klipper's graph draws them),
  /// whichever column is analysed; empty for a table.
  std::vector<AxisSpectrum> axes;
  /// A Klipper input that Klipper's calibrate_shaper normalises before scoring it (a raw
  /// accelerometer file, a PSD file without shaper columns): TEST_RESONANCES drives the axis at an
  /// acceleration ∝ f (resonance_tester.py: accel = accel_per_hz · freq), and calibrate_shaper
  /// divides the PSD by f + 0.1 Hz. recommend scores such a spectrum so (remaining.hpp,
  /// scored_spectrum); its modes are found on the PSD as measured.
  bool klipper_normalizes = false;
  std::size_t segments = 0;       ///< Welch segments averaged (0: a PSD file, unknown)
  double resolution_hz = 0.0;     ///< fs / segment length (a PSD file: its bin spacing)
  std::optional<UniformSeries> series;  ///< the analysed time record (not for a PSD file)
};

struct SpectrumRequest {
  std::filesystem::path path;
  /// Table: the column's name or 1-based index (required). Klipper raw: accel_x|accel_y|accel_z
  /// or xyz (the sum of the three axes' PSDs, Klipper's psd_xyz); x, y, z are accepted too.
  /// Klipper PSD: psd_x|psd_y|psd_z|psd_xyz (or x, y, z, xyz). Empty for Klipper files: xyz.
  std::string column;
  std::string time_column;          ///< table only; empty: io::require_time_column's defaults
  std::optional<double> from_s;     ///< window start (time records), s from the record's start
  std::optional<double> to_s;       ///< window end
  double segment_s = 0.0;           ///< Welch segment length; 0 = automatic (see spectrum_of_series)
};

/// The unit of a column's PSD from its name's unit suffix (docs/design.md §4): "gyro_deg_s" →
/// "(deg/s)²/Hz", "accel_m_s2" → "(m/s²)²/Hz", "input_v" → "V²/Hz"; a name without a known suffix
/// → "(unit of NAME)²/Hz".
std::string psd_unit_of_column(std::string_view column);

/// Reads one recording and returns its spectrum. Throws InputError (file, line, field) for bad
/// content, InvalidArgument for a bad column, window or segment.
MeasuredSpectrum load_spectrum(const SpectrumRequest& request);

/// Welch PSD of a uniformly sampled record. Segment: `segment_s` rounded to samples, or (0) the
/// largest power of two ≤ N/4 (≥ 64, ≤ N), so that about seven segments are averaged; the FFT is
/// zero-padded to 4× the segment (a finer grid for peak and half-power interpolation).
MeasuredSpectrum spectrum_of_series(const UniformSeries& series, double segment_s);

}  // namespace clearshape::advise
