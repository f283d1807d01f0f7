#pragma once
// Residual-vibration level of a response (thesis Eq. 5.1, §5.1.2):
//   MD = sqrt( Σ_{i=k}^{N−1} (M − s_i)² / n ),  n = N − k,
// where M is the mean of the response in steady state and k, the start of the steady state,
// is "the first coincide point of the system response and the mean".
//
// How k and M are computed (the thesis gives no algorithm; this is our reading):
//   1. M₀ = mean of the last `final_window_fraction` of the samples (the final window).
//   2. k(M) = the first sample index i >= the search start at which the response meets M, by
//      either of two rules:
//      crossing    s_i == M, or s_i − M has the opposite sign of s_{i−1} − M (the sample at or
//                  just after the crossing). For a step response that is the first time the
//                  rising edge reaches M, so the overshoot and the ringing count as residual
//                  vibration (Fig. 5.9).
//      band entry  |s_j − M| <= b for every j in [i, i + L): the response enters the band ±b
//                  around M and stays in it for `band_dwell_s` (L samples, or until the record
//                  ends).
//      k(M) is the earlier of the two; the result names the rule that decided it.
//      Both rules look only from the departure j(M) on: the first sample at which |s_j − M|
//      reaches half the largest |s_i − M| of the search range. A response must leave its mean
//      before it can meet it. For a step on an angle the first sample is that far (unless the
//      overshoot exceeds the move), so j is the search start; for a response that begins at
//      its steady mean — the link RATE during a position step, 0 before and after — j is on
//      the move's rising edge and the meeting is the return, as for an angle. Without it the
//      rest before the move (a noise-free gyroscope reads exactly 0 LSB = M; or it sits just
//      below a slightly positive M and the rising edge crosses it) was the "first coincide
//      point", the iteration put M at the mean rate of the whole move and MD measured the move
//      (28 °/s against 0.22 °/s from the link rate, 20° ZVDD step, calibrated rig).
//   3. M_{m+1} = mean(s_k … s_{N−1}) with k = k(M_m); repeat until k stops changing. At the
//      fixed point M is exactly the mean of the samples that enter Eq. 5.1 and k is the first
//      point where the response meets that mean. A repeated k that is not the previous one (a
//      cycle) or `max_iterations` ends the iteration with converged = false.
//
// Why a band: a well-shaped or well-damped response approaches its mean from one side and, being
// smooth, may not cross it for seconds (a ZVDD-shaped 20° step on the integrated gyro angle
// crosses only when the gyro's drift happens to carry it over M, 4 s after the move). The pure
// crossing rule then puts k near the end of the record, Eq. 5.1 covers a fraction of a second of
// it, and MD is both too small and erratic from trial to trial. "Coincide" is read as "agrees
// within what can be resolved": the band half-width is fixed once, before the iteration,
//   b = max(band_noise_multiple · σ_n, band_move_fraction · |M₀ − s_first|),
// where s_first is the first sample of the search range (the value before the last move) and
// σ_n is the sample-to-sample noise floor of the final window, estimated from first differences
// σ_n² = Σ (s_{i+1} − s_i)² / (2 (n − 1)) (von Neumann et al. 1941, Ann. Math. Stat. 12: the
// mean square successive difference, insensitive to slow drift).
// Defaults, and why:
//   band_move_fraction 0.5 %  the order of a servo's settling tolerance and well below the
//                             thesis rig's unshaped residual (MD ≈ 1.5 % of the step). On the
//                             simulated thesis rig 0.2 % still leaves starts 3–4 s late in a
//                             few shaped trials, 1 % lets a 56° low-jerk step start on its
//                             rising edge; 0.5 % starts every shaped trial within 1 s of the move.
//   band_noise_multiple 0     a noisy response already crosses M as soon as it is within about
//                             two noise σ of it (a spike carries it over), so the crossing rule
//                             is itself a noise band; a noise term would only move the start
//                             earlier, and ringing near the sampling rate cannot be told from
//                             noise by σ_n. Set it (e.g. 3) for quantized or spiky records that
//                             never cross.
//   band_dwell_s 0.1 s        one period of a 10 Hz mode, three 30 Hz position updates: a spike
//                             or a ringing peak that touches the band leaves it again well
//                             within it, a settled response stays. An oscillating response
//                             crosses M before it can stay inside the band, so for ringing
//                             responses the crossing rule decides, exactly as without a band.
// band_half_width >= 0 overrides the computed b (0: the crossing rule alone).
//
//   The search starts at the first sample at or after `search_from_s`; a sign change counts only
//   between two samples that are both at or after the departure. Several fixed points can exist; the
//   iteration returns the one reached from M₀, deterministically. A response that never meets
//   its mean (no crossing, never inside the band) takes k = the first sample of the final window.
#include <cstddef>
#include <limits>
#include <string_view>

#include "clearshape/core/series.hpp"

namespace clearshape::metrics {

struct MeanDeviationOptions {
  double final_window_fraction = 0.2;  ///< (0, 1]: share of the record that gives M₀ and σ_n
  double search_from_s = -std::numeric_limits<double>::infinity();  ///< ignore earlier samples
  int max_iterations = 100;
  double band_noise_multiple = 0.0;   ///< >= 0: b >= this · σ_n (noise floor of the final window)
  double band_move_fraction = 0.005;  ///< [0, 1): b >= this · |M₀ − first searched sample|
  double band_dwell_s = 0.1;          ///< >= 0: time the response must stay inside ±b
  /// >= 0 overrides the computed band half-width (0: the crossing rule alone); NaN: computed.
  double band_half_width = std::numeric_limits<double>::quiet_NaN();
};

/// Which rule put the start k of the steady state.
enum class StartRule {
  crossing,      ///< the response reached or crossed M at k
  band_entry,    ///< the response entered ±b around M at k and stayed for the dwell
  window_start,  ///< it never met M: k = first sample of the final window
};
std::string_view to_string(StartRule rule) noexcept;  ///< "crossing", "band-entry", "window-start"

struct MeanDeviationResult {
  double mean_deviation = 0.0;  ///< MD, in the units of the response
  double steady_mean = 0.0;     ///< M
  std::size_t start_index = 0;  ///< k
  double start_time_s = 0.0;    ///< time of sample k
  std::size_t samples = 0;      ///< n = N − k
  int iterations = 0;
  bool converged = false;
  StartRule start_rule = StartRule::crossing;  ///< what decided k at the end
  double band_half_width = 0.0;  ///< b, in the units of the response
  double noise_floor = 0.0;      ///< σ_n of the final window, in the units of the response
};

/// Eq. 5.1. Throws InvalidArgument for fewer than 2 samples, non-finite samples, options out of
/// range, or a `search_from_s` after the last sample.
MeanDeviationResult mean_deviation(const UniformSeries& response,
                                   const MeanDeviationOptions& options = {});

}  // namespace clearshape::metrics
