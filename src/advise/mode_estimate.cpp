#include "clearshape/advise/mode_estimate.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/dsp/peaks.hpp"
#include "clearshape/ident/modes.hpp"
#include "peak_fit.hpp"
#include "resonance_check.hpp"

namespace clearshape::advise {

namespace {

// Shoulders: the line fitted down to 10 % of the peak is wider than this × the peak's own
// half-power band (seeded noise-driven lines stay below 1.6; the golden two-mode record 1.59).
constexpr double kShoulderWidthRatio = 2.0;

// Hann's (and Kaiser β = 6's) 3-dB main-lobe width, in bins of the segment (Harris 1978, Table 1).
constexpr double kWindowHalfPowerBins = 1.44;

// Where the power falls through `level` walking from `peak` in direction `step` (±1), linearly
// interpolated between bins; the last bin when it never does.
double crossing(const MeasuredSpectrum& s, std::size_t peak, int step, double level, std::size_t lowest) {
  std::size_t k = peak;
  while (true) {
    const bool at_end = step < 0 ? k <= lowest : k + 1 >= s.power.size();
    if (at_end) return s.frequency_hz[k];
    const std::size_t next = step < 0 ? k - 1 : k + 1;
    if (s.power[next] < level) {
      const double t = (s.power[k] - level) / (s.power[k] - s.power[next]);
      return s.frequency_hz[k] + t * (s.frequency_hz[next] - s.frequency_hz[k]);
    }
    k = next;
  }
}

// The Lorentzian width inside a measured half-power width, the window's width taken as Gaussian:
// the inverse of Olivero & Longbothum's (1977) Voigt width fV ≈ 0.5346 fL + √(0.2166 fL² + fG²).
double lorentzian_width(double measured, double window) {
  if (measured <= window) return 0.0;
  const double a = 0.2858 - 0.2166, b = -1.0692 * measured, c = measured * measured - window * window;
  return (-b - std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a);
}

// Bounds of the bins that belong to a peak: down to 10 % of its power, within [f/2, 2f] and
// the given limits (the valley towards another mode).
std::pair<std::size_t, std::size_t> line_region(const MeasuredSpectrum& s, std::size_t bin, std::size_t lo, std::size_t hi) {
  const double level = 0.1 * s.power[bin], f = s.frequency_hz[bin];
  std::size_t a = bin, b = bin;
  while (a > lo && s.power[a - 1] >= level && s.frequency_hz[a - 1] >= 0.5 * f) --a;
  while (b < hi && s.power[b + 1] >= level && s.frequency_hz[b + 1] <= 2.0 * f) ++b;
  return {a, b};
}

// The half-power band of a peak, found on the spectrum averaged over ±1 resolution bin (Welch's
// scatter ripples a line on that scale; an unsmoothed walk stops at the first ripple).
std::pair<std::size_t, std::size_t> half_power_region(const MeasuredSpectrum& s, std::size_t bin, std::size_t lo, std::size_t hi) {
  const double grid = s.frequency_hz.size() > 1 ? s.frequency_hz[1] - s.frequency_hz[0] : s.resolution_hz;
  const auto h = static_cast<std::size_t>(std::max(1.0, std::round(s.resolution_hz / grid)));
  const auto mean_at = [&](std::size_t k) {
    const std::size_t a = k > lo + h ? k - h : lo, b = std::min(hi, k + h);
    double sum = 0.0;
    for (std::size_t i = a; i <= b; ++i) sum += s.power[i];
    return sum / static_cast<double>(b - a + 1);
  };
  const double level = 0.5 * mean_at(bin), f = s.frequency_hz[bin];
  std::size_t a = bin, b = bin;
  while (a > lo && mean_at(a - 1) >= level && s.frequency_hz[a - 1] >= 0.5 * f) --a;
  while (b < hi && mean_at(b + 1) >= level && s.frequency_hz[b + 1] <= 2.0 * f) ++b;
  return {a, b};
}

struct PeakStart {
  std::size_t bin = 0;
  double frequency_hz = 0.0;
  double damping_ratio = 0.0;
};

double grid_of(const MeasuredSpectrum& s) {
  return s.frequency_hz.size() > 1 ? s.frequency_hz[1] - s.frequency_hz[0] : s.resolution_hz;
}

// Start values at a peak bin: the parabola's vertex and the half-power crossings (noisy: Welch's
// scatter ripples the line, the fit does better).
PeakStart start_at(const MeasuredSpectrum& s, std::size_t bin, std::size_t lo) {
  const double grid = grid_of(s);
  PeakStart p{bin, s.frequency_hz[bin], 0.0};
  if (bin > 0 && bin + 1 < s.power.size()) {
    // Vertex of the parabola through the peak bin and its neighbours (sub-bin frequency).
    const double ym = s.power[bin - 1], y0 = s.power[bin], yp = s.power[bin + 1];
    const double curvature = ym - 2.0 * y0 + yp;
    if (curvature < 0.0) p.frequency_hz += grid * (ym - yp) / (2.0 * curvature);
  }
  const double width = crossing(s, bin, +1, 0.5 * s.power[bin], lo) - crossing(s, bin, -1, 0.5 * s.power[bin], lo);
  p.damping_ratio = std::clamp(width / (2.0 * p.frequency_hz), grid / p.frequency_hz, 0.5);
  return p;
}

// Neighbouring bins are correlated (zero padding, the window, overlapping segments): the fit's
// covariance is inflated by 3 × the zero-padding factor, calibrated by a Monte Carlo of seeded
// records (tests/advise/test_mode_coverage.cpp) to unit spread of the standardised errors.
double bin_correlation(const MeasuredSpectrum& s) {
  const double resolution = s.resolution_hz > 0.0 ? s.resolution_hz : grid_of(s);
  return 3.0 * resolution / grid_of(s);
}

// `band_zeta`: the ζ of the peak's half-power band (half_power_region; uncorrected). A fitted line
// wider than kShoulderWidthRatio × that was widened by shoulders: ζ is then the geometric mean of
// the two, and the range the data cannot exclude (ModeEstimate::damping_ratio_range) spans both.
ModeEstimate from_fit(const MeasuredSpectrum& s, const PeakStart& start, const detail::LineFit& fit,
                      std::optional<double> band_zeta = std::nullopt) {
  ModeEstimate m;
  m.source = "spectrum";
  m.peak_power = s.power[start.bin];
  const double resolution = s.resolution_hz > 0.0 ? s.resolution_hz : grid_of(s);
  const double window = kWindowHalfPowerBins * resolution;
  const double f0 = fit.converged ? fit.frequency_hz : start.frequency_hz;
  const double measured = 2.0 * (fit.converged ? fit.damping_ratio : start.damping_ratio) * f0;
  // A line no wider than the window is unresolved: its width is known only to lie below the
  // window's; take half of it (the σ below covers the rest).
  const double width = std::max(lorentzian_width(measured, window), 0.5 * window);
  // Half-power bandwidth of a mode: Δf = 2ζ fn (exact for a rate sensor's |jωH|², e.g. a gyro).
  m.frequency_hz = f0;
  m.damping_ratio = width / (2.0 * f0);
  m.half_power_low_hz = f0 * (std::sqrt(1.0 + m.damping_ratio * m.damping_ratio) - m.damping_ratio);
  m.half_power_high_hz = f0 * (std::sqrt(1.0 + m.damping_ratio * m.damping_ratio) + m.damping_ratio);
  // 1σ: the fit's covariance (without a fit: the grid and Welch's scatter); half the offset
  // between a rate sensor's peak (the model's) and a displacement or acceleration sensor's
  // (~ζ² f); a quarter of the window correction.
  const double bias = 0.5 * f0 * m.damping_ratio * m.damping_ratio;
  const double correction_sd = std::max(0.25 * std::abs(measured - width), measured <= window ? 0.5 * window : 0.0) / (2.0 * f0);
  if (fit.converged) {
    m.frequency_std_hz = std::sqrt(fit.frequency_var + bias * bias);
    m.damping_ratio_std = std::sqrt(m.damping_ratio * m.damping_ratio * fit.log_damping_var + correction_sd * correction_sd);
  } else {
    const double k = static_cast<double>(std::max<std::size_t>(1, s.segments));
    const double grid_sd = grid_of(s) / std::sqrt(12.0);
    m.frequency_std_hz = std::sqrt(grid_sd * grid_sd + 0.25 * width * width / k + bias * bias);
    m.damping_ratio_std = std::sqrt(m.damping_ratio * m.damping_ratio / k + std::pow(grid_sd / f0, 2) + correction_sd * correction_sd);
  }
  // The band was found on the spectrum averaged over ±1 resolution bin: its width is widened by
  // that boxcar (2 bins) and the window (1.44 bins), both taken as Gaussian (as above).
  const double band = band_zeta ? lorentzian_width(2.0 * *band_zeta * f0, std::hypot(2.0, kWindowHalfPowerBins) * resolution) / (2.0 * f0)
                                : 0.0;
  if (fit.converged && band > 0.0 && m.damping_ratio > kShoulderWidthRatio * band) {
    const double fitted = m.damping_ratio;
    m.damping_ratio = std::sqrt(fitted * band);
    m.damping_ratio_std = std::max(m.damping_ratio_std, 0.25 * (fitted - band));
    m.damping_ratio_range = {band, fitted};
    m.half_power_low_hz = f0 * (std::sqrt(1.0 + m.damping_ratio * m.damping_ratio) - m.damping_ratio);
    m.half_power_high_hz = f0 * (std::sqrt(1.0 + m.damping_ratio * m.damping_ratio) + m.damping_ratio);
    m.note = fmt::format("shoulders: the line fitted down to 10 % of the peak has ζ {:.3g}, the peak's half-power band {:.3g}; "
                         "ζ is their geometric mean and the worst case covers both",
                         fitted, band);
  }
  return m;
}

detail::LineFit fit_one(const MeasuredSpectrum& s, const PeakStart& p, std::pair<std::size_t, std::size_t> region) {
  return detail::fit_lines(s.frequency_hz, s.power, region.first, region.second, {{p.frequency_hz, p.damping_ratio}}, false, {},
                           bin_correlation(s))
      .lines.front();
}

// The first spectrum with the others interpolated onto its grid and added.
MeasuredSpectrum combined(const std::vector<MeasuredSpectrum>& spectra) {
  MeasuredSpectrum sum = spectra.front();
  sum.series.reset();
  for (std::size_t i = 1; i < spectra.size(); ++i) {
    const auto& o = spectra[i];
    for (std::size_t k = 0; k < sum.frequency_hz.size(); ++k) {
      const double f = sum.frequency_hz[k];
      const auto it = std::lower_bound(o.frequency_hz.begin(), o.frequency_hz.end(), f);
      if (it == o.frequency_hz.end() || (it == o.frequency_hz.begin() && *it > f)) continue;
      const std::size_t j = static_cast<std::size_t>(it - o.frequency_hz.begin());
      double p = o.power[j];
      if (*it > f) {
        const double t = (f - o.frequency_hz[j - 1]) / (o.frequency_hz[j] - o.frequency_hz[j - 1]);
        p = o.power[j - 1] + t * (o.power[j] - o.power[j - 1]);
      }
      sum.power[k] += p;
    }
    sum.segments = std::min(sum.segments, o.segments);
  }
  return sum;
}

// The first line (peak bin `top`, start p1) and a candidate second one (peak bin `cand`), fitted
// together; nullopt unless the second is significant and a usable resonance.
std::optional<std::vector<ModeEstimate>> two_lines(const MeasuredSpectrum& s, const ModeEstimateOptions& options, const PeakStart& p1,
                                                   std::size_t top, std::size_t cand, std::size_t lowest) {
  const std::size_t end = s.power.size() - 1;
  // Each line's own band ends at the valley between the two; both are then fitted together.
  const std::size_t a = std::min(top, cand), b = std::max(top, cand);
  std::size_t valley = a;
  for (std::size_t k = a; k <= b; ++k) {
    if (s.power[k] < s.power[valley]) valley = k;
  }
  const auto r1 = top < cand ? line_region(s, top, lowest, valley) : line_region(s, top, valley, end);
  const auto r2 = cand < top ? line_region(s, cand, lowest, valley) : line_region(s, cand, valley, end);
  const PeakStart p2 = start_at(s, cand, lowest);
  const detail::LineFit one = fit_one(s, p1, r1), two = fit_one(s, p2, r2);
  // Both lines together: their powers adding (independent excitation) or their responses adding
  // with residues of either relative sign (one input drives both); the best fit wins.
  const std::vector<detail::LineStart> starts{
      {one.converged ? one.frequency_hz : p1.frequency_hz, one.converged ? one.damping_ratio : p1.damping_ratio},
      {two.converged ? two.frequency_hz : p2.frequency_hz, two.converged ? two.damping_ratio : p2.damping_ratio}};
  const std::size_t from = std::min(r1.first, r2.first), to = std::max(r1.second, r2.second);
  detail::LinesFit best;
  for (const auto& [coherent, sign] : {std::pair{false, 1.0}, std::pair{true, 1.0}, std::pair{true, -1.0}}) {
    detail::LinesFit fit = detail::fit_lines(s.frequency_hz, s.power, from, to, starts, coherent, {1.0, sign}, bin_correlation(s));
    if (fit.converged && (!best.converged || fit.cost < best.cost)) best = std::move(fit);
  }
  // The second line must explain the band: one line fitted over the same band leaves a cost
  // larger by more than chance allows for three more parameters (Δcost / (c·s²) > 16.3, the
  // χ²(3) 0.1 % point; c the bin correlation, s² the two-line fit's residual variance).
  const detail::LinesFit alone =
      detail::fit_lines(s.frequency_hz, s.power, from, to, {{p1.frequency_hz, p1.damping_ratio}}, false, {}, bin_correlation(s));
  const double bins = static_cast<double>(to - from + 1);
  if (best.converged && alone.converged) {
    const double s2 = best.cost / std::max(1.0, bins - 6.0);
    if ((alone.cost - best.cost) / (bin_correlation(s) * s2) < 16.3) return std::nullopt;
  }
  const bool joint = best.converged;
  const detail::LineFit& fit_a = joint ? best.lines[0] : one;
  const detail::LineFit& fit_b = joint ? best.lines[1] : two;
  // The second line must be a usable resonance too (standing out of its floor, ζ off the bounds).
  const detail::LineVerdict verdict2 = detail::judge_line(s, fit_b, p2.frequency_hz, s.power[cand], lowest, options.min_prominence);
  if (!verdict2.problem.empty()) return std::nullopt;
  std::vector<ModeEstimate> out{from_fit(s, p1, fit_a), from_fit(s, p2, fit_b)};
  out[0].prominence = detail::judge_line(s, fit_a, p1.frequency_hz, s.power[top], lowest, options.min_prominence).prominence;
  out[1].prominence = verdict2.prominence;
  return out;
}

}  // namespace

std::vector<ModeEstimate> spectral_modes(const MeasuredSpectrum& s, const ModeEstimateOptions& options) {
  if (options.max_modes < 1 || options.max_modes > 2) throw_invalid("max_modes", static_cast<double>(options.max_modes), "1 or 2");
  if (s.power.size() < 3 || s.power.size() != s.frequency_hz.size()) {
    throw InvalidArgument(fmt::format("{}: a spectrum needs at least three bins", s.source));
  }
  // Below two resolution bins the window's main lobe from DC (and drift) hides any mode.
  const double min_f = options.min_frequency_hz ? *options.min_frequency_hz : 2.0 * s.resolution_hz;
  std::size_t lowest = 0;
  while (lowest < s.frequency_hz.size() && s.frequency_hz[lowest] < min_f) ++lowest;
  const auto refuse = [&](const std::string& why) {
    return NoUsableResonance(fmt::format("no usable resonance in {}: {}; {}", s.source, why, detail::what_to_record()));
  };
  if (lowest + 3 > s.power.size()) throw refuse(fmt::format("no bins above {:.4g} Hz", min_f));
  std::vector<double> p(s.power.begin() + static_cast<std::ptrdiff_t>(lowest), s.power.end());
  std::vector<dsp::Peak> peaks = dsp::find_peaks(p);
  if (peaks.empty()) throw refuse(fmt::format("the spectrum has no peak above {:.4g} Hz", min_f));
  std::stable_sort(peaks.begin(), peaks.end(), [](const dsp::Peak& a, const dsp::Peak& b) { return a.height > b.height; });
  const std::size_t top = peaks.front().index + lowest, end = s.power.size() - 1;
  const PeakStart p1 = start_at(s, top, lowest);
  detail::LineFit fit1 = fit_one(s, p1, line_region(s, top, lowest, end));
  // Shoulders (other lines, forced response) inside the band down to 10 % can widen the fitted
  // line: cross-checked against the width of the peak's own half-power band.
  const auto band = half_power_region(s, top, lowest, end);
  const double band_zeta = (s.frequency_hz[band.second] - s.frequency_hz[band.first]) / (2.0 * s.frequency_hz[top]);
  const detail::LineVerdict verdict1 = detail::judge_line(s, fit1, p1.frequency_hz, s.power[top], lowest, options.min_prominence);
  if (!verdict1.problem.empty()) throw refuse(verdict1.problem);
  ModeEstimate single = from_fit(s, p1, fit1, band_zeta);
  single.prominence = verdict1.prominence;
  if (options.max_modes > 1) {
    // A second mode is found by significance, not by its height relative to the first: the
    // highest peaks that stand out of their own local floor are tried in turn, and the two-line
    // fit must beat one line by more than chance allows (two_lines).
    std::size_t tries = 0;
    for (std::size_t i = 1; i < peaks.size() && tries < options.second_peak_tries; ++i) {
      const auto& pk = peaks[i];
      const std::size_t bin = pk.index + lowest;
      const double f = s.frequency_hz[bin];
      if (pk.height < options.second_peak_min_ratio * s.power[top]) break;  // sorted: no later one is relevant
      if (!(pk.height >= options.min_prominence * detail::local_floor(s, f, lowest))) continue;
      // Ripples of Welch's scatter on a line have little prominence; a mode stands out ...
      if (pk.prominence < options.second_peak_min_prominence * pk.height) continue;
      // (outside the first peak's own half-power crossings and a resolution bin: a broad one-line
      // fit over two merged lines would hide the second)
      if (std::abs(f - p1.frequency_hz) <= p1.damping_ratio * p1.frequency_hz + s.resolution_hz) continue;
      ++tries;
      if (auto two = two_lines(s, options, p1, top, bin, lowest)) return *two;
    }
  }
  return {single};
}

ModeEstimation estimate_modes(const std::vector<MeasuredSpectrum>& spectra, const ModeEstimateOptions& options) {
  if (spectra.empty()) throw InvalidArgument("estimate_modes: no spectra");
  ModeEstimation r;
  r.spectral_modes = spectral_modes(spectra.size() == 1 ? spectra.front() : combined(spectra), options);
  r.modes = r.spectral_modes;
  if (!options.free_decay_fit) {
    r.note = "free-decay fit not requested";
    return r;
  }
  const auto with_series = std::find_if(spectra.begin(), spectra.end(), [](const auto& s) { return s.series.has_value(); });
  if (with_series == spectra.end()) {
    r.note = "no single time record (a PSD file or Klipper's xyz sum): spectral estimates only";
    return r;
  }
  const UniformSeries& y = *with_series->series;
  if (y.size() > options.free_decay_max_samples) {
    r.note = fmt::format("record of {} samples is longer than {}: free-decay fit skipped (give --from-s/--to-s around the decay)",
                         y.size(), options.free_decay_max_samples);
    return r;
  }
  ident::ModeOptions mo;
  mo.modes = r.spectral_modes.size();
  ident::ModeIdentification fit;
  try {
    fit = ident::identify_free_response_modes(y, mo);
  } catch (const std::exception& e) {
    r.note = fmt::format("free-decay fit failed ({}): spectral estimates only", e.what());
    return r;
  }
  r.free_decay_fit_percent = fit.fit_percent;
  if (!(fit.fit_percent >= 80.0) || fit.modes.size() < r.spectral_modes.size()) {
    r.note = fmt::format("the record is not a free decay (damped-sinusoid fit {:.1f} % < 80 %, {} modes): spectral estimates only",
                         fit.fit_percent, fit.modes.size());
    return r;
  }
  std::vector<ModeEstimate> fitted;
  for (const ModeEstimate& sm : r.spectral_modes) {
    // The fitted mode nearest the spectral one must lie within the spectral peak's half-power band.
    const ident::ModeEstimate* best = nullptr;
    for (const auto& fm : fit.modes) {
      if (!best || std::abs(fm.natural_frequency_hz() - sm.frequency_hz) < std::abs(best->natural_frequency_hz() - sm.frequency_hz)) best = &fm;
    }
    // (A decay starts under the Welch window's rising edge, which pulls the spectral peak: the
    // fitted mode need only lie within the peak's half-power half-width plus 3σ of it.)
    const double tol = 0.5 * (sm.half_power_high_hz - sm.half_power_low_hz) + 3.0 * sm.frequency_std_hz;
    // (and be a decaying mode: ζ ≤ 0 is an unstable pole, ζ ≥ 1 no oscillation)
    if (!best || std::abs(best->natural_frequency_hz() - sm.frequency_hz) > tol || !std::isfinite(best->natural_frequency_std_rad_s) ||
        !std::isfinite(best->damping_ratio_std) || !(best->damping_ratio > 0.0 && best->damping_ratio < 1.0)) {
      r.note = fmt::format("the free-decay fit ({:.1f} %) does not confirm the spectral peak at {:.4g} Hz: spectral estimates only",
                           fit.fit_percent, sm.frequency_hz);
      return r;
    }
    ModeEstimate m = sm;
    m.frequency_hz = best->natural_frequency_hz();
    m.frequency_std_hz = best->natural_frequency_std_hz();
    m.damping_ratio = best->damping_ratio;
    m.damping_ratio_std = best->damping_ratio_std;
    m.source = "free-decay fit";
    fitted.push_back(m);
  }
  r.modes = std::move(fitted);
  r.free_decay_used = true;
  r.note = fmt::format("free decay: damped-sinusoid fit {:.1f} % (ident::modes) gives the modes and their 1σ", fit.fit_percent);
  return r;
}

}  // namespace clearshape::advise
