#pragma once
// Readers of Klipper's two resonance files (private to advise): the raw accelerometer CSV
// ("#time,accel_x,accel_y,accel_z") and the PSD CSV ("freq,psd_x,psd_y,psd_z,psd_xyz[,shapers:,…]").
#include <array>
#include <string>
#include <string_view>
#include <vector>

namespace clearshape::advise::detail {

struct KlipperRaw {
  std::vector<double> time_s;
  std::array<std::vector<double>, 3> accel;  ///< x, y, z
};

struct KlipperPsd {
  std::vector<double> frequency_hz;
  std::array<std::vector<double>, 4> psd;    ///< x, y, z, xyz
  /// The header has Klipper's "shapers:" columns: calibrate_shaper wrote the PSD already divided
  /// by (f + 0.1 Hz) (shaper_calibrate.py, normalize_to_frequencies).
  bool normalized = false;
};

/// Throws InputError (source, line, field) for a bad header, a short row, a non-numeric or
/// non-finite value, time not increasing, or fewer than two rows.
KlipperRaw parse_klipper_raw(std::string_view text, const std::string& source);
/// Throws InputError for a bad header, a short row, a non-numeric, non-finite or negative value,
/// frequencies not increasing, or fewer than three rows.
KlipperPsd parse_klipper_psd(std::string_view text, const std::string& source);

}  // namespace clearshape::advise::detail
