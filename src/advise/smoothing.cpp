#include "clearshape/advise/smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "clearshape/core/error.hpp"

namespace clearshape::advise {

namespace {

// The sums both corner offsets are made of, about the shaper's centroid t_s = Σ A_i t_i / Σ A_i
// (Klipper, klippy/extras/shaper_calibrate.py, _get_shaper_smoothing):
//   90°:  √2 / ΣA · Σ_{t_i ≥ t_s} A_i (v_sc + a/2 · (t_i − t_s)) (t_i − t_s)
//   180°: 1 / ΣA · Σ_i A_i a/2 · (t_i − t_s)²
struct CornerSums {
  double late_first = 0.0;    ///< Σ_{t_i ≥ t_s} A_i (t_i − t_s) / ΣA
  double late_second = 0.0;   ///< Σ_{t_i ≥ t_s} A_i (t_i − t_s)² / ΣA
  double all_second = 0.0;    ///< Σ_i A_i (t_i − t_s)² / ΣA
};

CornerSums corner_sums(const shaping::Shaper& shaper) {
  double total = 0.0, moment = 0.0;
  for (const auto& i : shaper.impulses()) {
    total += i.amplitude;
    moment += i.amplitude * i.time_s;
  }
  const double centroid_s = moment / total;
  CornerSums s;
  for (const auto& i : shaper.impulses()) {
    const double dt_s = i.time_s - centroid_s;
    if (i.time_s >= centroid_s) {
      s.late_first += i.amplitude * dt_s;
      s.late_second += i.amplitude * dt_s * dt_s;
    }
    s.all_second += i.amplitude * dt_s * dt_s;
  }
  s.late_first /= total;
  s.late_second /= total;
  s.all_second /= total;
  return s;
}

}  // namespace

double smoothing_mm(const shaping::Shaper& shaper, double accel_mm_s2, double square_corner_velocity_mm_s) {
  require_non_negative("smoothing acceleration (mm/s²)", accel_mm_s2);
  require_non_negative("square-corner velocity (mm/s)", square_corner_velocity_mm_s);
  const CornerSums s = corner_sums(shaper);
  const double half_accel = 0.5 * accel_mm_s2;
  const double offset_90 = std::sqrt(2.0) * (square_corner_velocity_mm_s * s.late_first + half_accel * s.late_second);
  const double offset_180 = half_accel * s.all_second;
  return std::max(offset_90, offset_180);
}

double max_accel_mm_s2(const shaping::Shaper& shaper, double square_corner_velocity_mm_s, double target_smoothing_mm) {
  require_non_negative("square-corner velocity (mm/s)", square_corner_velocity_mm_s);
  require_positive("target smoothing (mm)", target_smoothing_mm);
  const CornerSums s = corner_sums(shaper);
  const double inf = std::numeric_limits<double>::infinity();
  // Each offset is c0 + c1·a: solve c0 + c1·a = target for each, keep the smaller a.
  const double c0_90 = std::sqrt(2.0) * square_corner_velocity_mm_s * s.late_first;
  const double c1_90 = 0.5 * std::sqrt(2.0) * s.late_second, c1_180 = 0.5 * s.all_second;
  if (c0_90 > target_smoothing_mm) return 0.0;
  const double a_90 = c1_90 > 0.0 ? (target_smoothing_mm - c0_90) / c1_90 : inf;
  const double a_180 = c1_180 > 0.0 ? target_smoothing_mm / c1_180 : inf;
  return std::min(a_90, a_180);
}

double klipper_score(double smoothing_mm, double remaining) {
  // Klipper's empirical score (shaper_calibrate.py, fit_shaper).
  return smoothing_mm * (std::pow(remaining, 1.5) + 0.2 * remaining + 0.01);
}

}  // namespace clearshape::advise
