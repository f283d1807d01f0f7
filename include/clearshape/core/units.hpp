#pragma once
// Unit conversions. SI inside the library; degrees only at the user-facing boundary.
#include <numbers>

namespace clearshape {

inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

constexpr double deg_to_rad(double angle_deg) noexcept { return angle_deg * kPi / 180.0; }
constexpr double rad_to_deg(double angle_rad) noexcept { return angle_rad * 180.0 / kPi; }
constexpr double hz_to_rad_s(double frequency_hz) noexcept { return frequency_hz * kTwoPi; }
constexpr double rad_s_to_hz(double frequency_rad_s) noexcept { return frequency_rad_s / kTwoPi; }

}  // namespace clearshape
