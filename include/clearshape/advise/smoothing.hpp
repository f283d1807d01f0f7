#pragma once
// A printer's cost of a shaper, as Klipper's calibrate_shaper measures it (docs/recommend.md,
// "Printer data"): the smoothing — how far a toolhead accelerating at a given acceleration and
// taking a corner at the square-corner velocity strays from its path because the shaper spreads
// the command in time — and the largest acceleration that keeps that smoothing under a target.
// Units are the printer's: mm, mm/s, mm/s². Impulse amplitudes need not sum to 1 (they are
// normalised by their sum, as Klipper does).
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::advise {

struct SmoothingSettings {
  double accel_mm_s2 = 5000.0;                  ///< the acceleration the smoothing is quoted at (Klipper: 5000)
  double square_corner_velocity_mm_s = 5.0;     ///< Klipper's default square_corner_velocity
  double target_smoothing_mm = 0.12;            ///< Klipper's TARGET_SMOOTHING for max_accel
};

/// The larger of the 90° and 180° corner offsets (mm) at `accel_mm_s2`. Throws InvalidArgument
/// for a negative acceleration or velocity.
double smoothing_mm(const shaping::Shaper& shaper, double accel_mm_s2 = 5000.0, double square_corner_velocity_mm_s = 5.0);

/// The largest acceleration (mm/s²) whose smoothing_mm is at most `target_smoothing_mm`; 0 when
/// even a vanishing acceleration exceeds it. Exact (both offsets are linear in the acceleration).
double max_accel_mm_s2(const shaping::Shaper& shaper, double square_corner_velocity_mm_s = 5.0,
                       double target_smoothing_mm = 0.12);

/// Klipper's score weighing remaining vibration v (a fraction) against smoothing:
/// smoothing · (v^1.5 + 0.2 v + 0.01); lower is better.
double klipper_score(double smoothing_mm, double remaining);

}  // namespace clearshape::advise
