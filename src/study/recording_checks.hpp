#pragma once
// The unit checks of a recording (docs/recordings.md, "Unit mistakes the reader catches"): each
// throws an InputError naming the file, the line (0 = the whole record), the column and the likely
// fix. Used by read_recording (recordings.cpp).
#include <cstddef>
#include <string>
#include <vector>

#include "clearshape/io/table.hpp"
#include "clearshape/study/recordings.hpp"

namespace clearshape::study::detail {

/// The spacing `step` of the time column `time` (in the declared `time_unit`) against the
/// protocol's sample time: a step 1000× (or 1/1000×) the protocol's is a time column in ms (in s)
/// and gets that hint; any other mismatch says to resample or set the protocol's sample_rate_hz.
void check_time_spacing(const io::Table& t, const std::string& time, const std::string& time_unit, double step_s,
                        double want_s, const std::string& protocol_name, double sample_rate_hz);

/// No link rate beyond the gyroscope's full scale (`gyro_full_scale_deg_s`; the ITG-3205's
/// ±2000 °/s by default) in the first `n` rows: a gyro cannot report more. `deg_s` is the column
/// converted to deg/s.
void check_gyro_full_scale(const io::Table& t, const RecordingColumns& c, const std::vector<double>& deg_s,
                           std::size_t n);

/// The link's travel (the rate integrated over the record, its range) against the motor's travel
/// (the range of the motor angle): a ratio near 57.3 or 1/57.3 is a deg/rad mistake, and a
/// difference beyond kTravelAllowanceDeg + kTravelAllowanceRelative × the motor's travel is more
/// than a play of a few degrees can explain. The gyro's rest offset (its mean rate before the
/// command first moves, when that is at least kTravelBiasMinSamples samples) is removed first.
void check_link_travel(const std::string& file, const RecordingColumns& c, const std::vector<double>& command,
                       const std::vector<double>& motor_deg, const std::vector<double>& link_deg_s,
                       double sample_time_s, std::size_t n);

inline constexpr double kTravelAllowanceDeg = 10.0;
inline constexpr double kTravelAllowanceRelative = 0.25;
inline constexpr std::size_t kTravelBiasMinSamples = 10;
/// When neither the link nor the motor travels this far (deg), the deg/rad ratio test is not made
/// (a rest trial has no travel).
inline constexpr double kTravelRatioMinDeg = 1.0;

}  // namespace clearshape::study::detail
