#include "clearshape/advise/recommend.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/grid.hpp"

namespace clearshape::advise {

namespace {

const std::vector<std::string> kSingle{"zv", "mzv", "zvd", "zvdd", "zvddd", "ei", "ei2", "ei3", "si"};

bool is_single(const std::string& name) { return std::find(kSingle.begin(), kSingle.end(), name) != kSingle.end(); }

// The shaper designed for 1 Hz, scaled to f Hz: at a fixed ζ every design's impulse times scale
// with 1/ωn and its amplitudes stay (Eq. 2.19 depends on ω·t only).
shaping::Shaper scaled(const shaping::Shaper& prototype, double frequency_hz) {
  std::vector<shaping::Impulse> out(prototype.impulses().begin(), prototype.impulses().end());
  for (auto& i : out) i.time_s /= frequency_hz;
  return shaping::Shaper(prototype.method(), std::move(out), shaping::Shaper::Normalize::no);
}

shaping::Shaper prototype(const std::string& name, double zeta, const RecommendOptions& o, double si_half_band) {
  shaping::DesignRequest r;
  r.method = shaping::method_from_string(name);
  r.mode = shaping::Mode::from_hz(1.0, zeta);
  r.vtol = o.vtol;
  if (r.method == shaping::Method::si) {
    shaping::SiOptions si;
    si.frequency_low_rad_s = kTwoPi * (1.0 - si_half_band);
    si.frequency_high_rad_s = kTwoPi * (1.0 + si_half_band);
    si.vtol = o.vtol;
    r.si = si;
  }
  return shaping::design(r);
}

struct Evaluator {
  const std::vector<WeightedBins>& bins;
  std::vector<std::vector<std::vector<double>>> zetas;  ///< [spectrum][test point][bin]: each bin's band's ζ
  std::vector<double> scales;
  const SmoothingSettings& printer;
  // Klipper's worst case over the test points, each bin at its own band's ζ of that point.
  double over(const shaping::Shaper& s, const std::vector<double>& sc) const {
    double w = 0.0;
    for (std::size_t i = 0; i < bins.size(); ++i) {
      for (const auto& z : zetas[i]) {
        for (const double scale : sc) w = std::max(w, remaining_vibration(s, bins[i], z, scale));
      }
    }
    return w;
  }
  double worst(const shaping::Shaper& s) const { return over(s, scales); }
  double nominal(const shaping::Shaper& s) const { return over(s, {1.0}); }
  double smoothing(const shaping::Shaper& s) const {
    return smoothing_mm(s, printer.accel_mm_s2, printer.square_corner_velocity_mm_s);
  }
};

const DampingBand& band_at(const std::vector<DampingBand>& bands, double frequency_hz) {
  for (const auto& b : bands) {
    if (b.mode && frequency_hz >= b.low_hz && frequency_hz <= b.high_hz) return b;
  }
  return bands.front();
}

Evaluator make_evaluator(const std::vector<WeightedBins>& bins, const std::vector<DampingBand>& bands, std::vector<double> scales,
                         const SmoothingSettings& printer) {
  std::size_t points = 0;
  for (const auto& b : bands) points = std::max(points, b.ratios.size());
  Evaluator ev{bins, {}, std::move(scales), printer};
  for (const auto& sb : bins) {
    std::vector<std::vector<double>> per_point(points, std::vector<double>(sb.frequency_hz.size()));
    for (std::size_t k = 0; k < sb.frequency_hz.size(); ++k) {
      const auto& ratios = band_at(bands, sb.frequency_hz[k]).ratios;
      for (std::size_t j = 0; j < points; ++j) per_point[j][k] = ratios[std::min(j, ratios.size() - 1)];
    }
    ev.zetas.push_back(std::move(per_point));
  }
  return ev;
}

std::vector<double> scan_grid(const RecommendOptions& o, double mode_hz) {
  if (!o.scan_frequencies_hz.empty()) return o.scan_frequencies_hz;
  const double lo = o.scan_ratio_low * mode_hz, hi = o.scan_ratio_high * mode_hz;
  std::vector<double> g;
  if (o.scan_step_hz) {
    const double step = std::max(*o.scan_step_hz, (hi - lo) / 200.0);
    for (std::size_t i = 0; lo + step * static_cast<double>(i) < hi; ++i) g.push_back(lo + step * static_cast<double>(i));
    return g;
  }
  // Log-spaced: f_i = lo·(1 + step)^i, every point a multiple of the mode, whatever the unit of time.
  const double ratio = 1.0 + o.scan_step_ratio;
  for (double f = lo; f < hi; f *= ratio) g.push_back(f);
  return g;
}

bool same_impulses(const shaping::Shaper& a, const shaping::Shaper& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    if (a.impulses()[i].time_s != b.impulses()[i].time_s ||
        !(std::abs(a.impulses()[i].amplitude - b.impulses()[i].amplitude) <= 1e-9)) {
      return false;
    }
  }
  return true;
}

struct ScanPoint {
  double frequency_hz = 0.0, remaining = 0.0, smoothing_mm = 0.0;
};

struct ScanResult {
  double selected_hz = 0.0, selected_v = 0.0, least_hz = 0.0, least_v = 0.0;
  std::vector<ScanPoint> points;  ///< ascending frequency (weigh_smoothing only)
};

// Klipper's frequency choice when smoothing is weighed (shaper_calibrate.py, fit_shaper): from
// the lowest frequency up, a near-best point replaces the pick when its score is lower.
void select_by_score(ScanResult& r, const RecommendOptions& o) {
  double best_score = std::numeric_limits<double>::infinity();
  for (const auto& p : r.points) {
    if (p.frequency_hz == r.least_hz) best_score = std::min(best_score, klipper_score(p.smoothing_mm, p.remaining));
  }
  for (const auto& p : r.points) {
    const double score = klipper_score(p.smoothing_mm, p.remaining);
    if (p.remaining < r.least_v * o.near_best_factor + o.near_best_offset && score < best_score) {
      best_score = score;
      r.selected_hz = p.frequency_hz;
      r.selected_v = p.remaining;
    }
  }
}

// Klipper's frequency fit: scan from the highest frequency down, keep the least remaining
// vibration (ties: the higher frequency), then take the highest frequency (shortest shaper)
// whose remaining vibration is below factor·least + offset.
// On an update grid a whole interval of design frequencies gives the same applied shaper; of
// those, the one nearest `prefer_hz` (the mode's frequency) is reported (it changes nothing
// that is applied, only the number a user reads and the off-grid design compared with it).
template <typename Make>
ScanResult scan(const std::vector<double>& grid, Make&& make, const Evaluator& ev, const RecommendOptions& o,
                double prefer_hz) {
  std::vector<std::pair<double, double>> results;  // (f, v), descending f
  ScanResult r;
  bool first = true;
  for (auto it = grid.rbegin(); it != grid.rend(); ++it) {
    const shaping::Shaper shaper = make(*it);
    const double v = ev.worst(shaper);
    results.emplace_back(*it, v);
    if (o.weigh_smoothing) r.points.push_back(ScanPoint{*it, v, ev.smoothing(shaper)});
    if (first || v < r.least_v) {
      r.least_v = v;
      r.least_hz = *it;
      first = false;
    }
  }
  r.selected_hz = r.least_hz;
  r.selected_v = r.least_v;
  std::reverse(r.points.begin(), r.points.end());
  if (o.weigh_smoothing) {
    select_by_score(r, o);
  } else {
    for (const auto& [f, v] : results) {
      if (v < r.least_v * o.near_best_factor + o.near_best_offset) {
        r.selected_hz = f;
        r.selected_v = v;
        break;
      }
    }
  }
  if (o.update_grid_hz > 0.0) {
    const shaping::Shaper chosen = make(r.selected_hz);
    for (const double f : grid) {
      if (std::abs(f - prefer_hz) < std::abs(r.selected_hz - prefer_hz) && same_impulses(make(f), chosen)) r.selected_hz = f;
    }
  }
  return r;
}

// A spectral line whose half-power width 2ζf spans at most unresolved_bins bins: the window's own
// width (Hann: 1.44 bins) is as wide, so the data bound its ζ from above but do not measure it.
bool unresolved(const ModeEstimate& m, double resolution_hz, const RecommendOptions& o) {
  return o.unresolved_bins > 0.0 && m.source == "spectrum" && resolution_hz > 0.0 &&
         2.0 * m.damping_ratio * m.frequency_hz <= o.unresolved_bins * resolution_hz;
}

std::string line_text(const ModeEstimate& m, std::size_t index, double resolution_hz) {
  const double width_hz = 2.0 * m.damping_ratio * m.frequency_hz;
  return fmt::format("mode {}'s line at {:.4g} Hz is unresolved (half-power width {:.3g} Hz = {:.2f} bins)", index + 1, m.frequency_hz,
                     width_hz, width_hz / resolution_hz);
}

// What a mode's data cannot exclude. Shoulders: the band's ζ … the fit's, not ζ ± 2σ about their
// geometric mean (that reaches below the peak's own half-power band, which the data do exclude;
// docs/recommend.md, "On real printers' spectra"). Else ζ ± max(2σ, ζ/4).
std::pair<double, double> mode_band(const ModeEstimate& m) {
  if (m.damping_ratio_range) return *m.damping_ratio_range;
  const double half = std::max(2.0 * m.damping_ratio_std, 0.25 * m.damping_ratio);
  return {m.damping_ratio - half, m.damping_ratio + half};
}

std::vector<double> evenly(double lo, double hi, std::size_t points) {
  lo = std::clamp(lo, 0.001, 0.9);
  hi = std::clamp(hi, lo, 0.9);
  std::vector<double> d;
  for (std::size_t i = 0; i < points; ++i) d.push_back(lo + (hi - lo) * static_cast<double>(i) / static_cast<double>(points - 1));
  return d;
}

// The band of an unresolved line: its own bins (within max(ζf, one bin) of it), over its ζ band
// widened up to the ζ of a line unresolved_bins bins wide (what the resolution cannot exclude).
DampingBand line_band(const ModeEstimate& m, std::size_t index, double resolution_hz, const RecommendOptions& o) {
  DampingBand b;
  const double half_hz = std::max(m.damping_ratio * m.frequency_hz, resolution_hz);
  b.low_hz = m.frequency_hz - half_hz;
  b.high_hz = m.frequency_hz + half_hz;
  auto [lo, hi] = mode_band(m);
  lo = std::max(lo, 0.001);  // evenly()'s floor
  const double bound = o.unresolved_bins * resolution_hz / (2.0 * m.frequency_hz);
  b.ratios = evenly(lo, std::max(hi, bound), o.damping_points);
  b.mode = index;
  b.reason = fmt::format("{}: its ζ band {:.3g}–{:.3g}, reaching at least a {:g}-bin-wide line's {:.3g}; the rest of the spectrum is tested without it",
                         line_text(m, index, resolution_hz), lo, hi, o.unresolved_bins, bound);
  return b;
}

// The test damping ratios, per band of bins. Printer data (a Klipper file) also covers Klipper's
// 0.075–0.15 (shaper_calibrate.py, TEST_DAMPING_RATIOS): a PSD file's 1.5–3 Hz bins leave a
// printer's lines two or three bins wide, too few to exclude them (docs/recommend.md, "On real
// printers' spectra"). An unresolved line's bins are tested over its own band, the rest without it
// ("Per-line damping bands"), unless the caller holds the band or no other line (nor printer data)
// gives the rest one.
std::vector<DampingBand> damping_bands(const std::vector<ModeEstimate>& modes, const RecommendOptions& o, double design, bool printer,
                                       double resolution_hz) {
  DampingBand rest;
  rest.high_hz = std::numeric_limits<double>::infinity();
  if (!o.test_damping_ratios.empty() || o.damping_points <= 1) {
    rest.ratios = o.test_damping_ratios.empty() ? std::vector<double>{design} : o.test_damping_ratios;
    rest.reason = o.test_damping_ratios.empty() ? "every bin: the design damping (one test point)" : "every bin: the caller's test damping ratios";
    return {rest};
  }
  const bool held = o.damping_low || o.damping_high;
  std::vector<bool> line(modes.size(), false);
  std::size_t lines = 0;
  for (std::size_t i = 0; i < modes.size() && !held; ++i) lines += (line[i] = unresolved(modes[i], resolution_hz, o)) ? 1 : 0;
  if (lines == modes.size() && !printer) std::fill(line.begin(), line.end(), false);  // nothing else bounds the rest
  double lo = printer ? 0.075 : 1.0, hi = printer ? 0.15 : 0.0;
  std::vector<std::string> from;
  if (printer) from.emplace_back("Klipper's 0.075–0.15 (printer data)");
  for (std::size_t i = 0; i < modes.size(); ++i) {
    if (line[i]) continue;
    const auto [a, b] = mode_band(modes[i]);
    lo = std::min(lo, a);
    hi = std::max(hi, b);
    from.push_back(fmt::format("mode {}'s ζ {:.3g}–{:.3g}", i + 1, a, b));
  }
  rest.ratios = evenly(o.damping_low.value_or(lo), o.damping_high.value_or(hi), o.damping_points);
  rest.reason = held ? "every bin: the caller's damping range"
                     : fmt::format("{}: {}", std::count(line.begin(), line.end(), true) > 0 ? "every bin outside the unresolved lines" : "every bin",
                                   fmt::join(from, ", "));
  std::vector<DampingBand> bands{rest};
  for (std::size_t i = 0; i < modes.size(); ++i) {
    if (line[i]) bands.push_back(line_band(modes[i], i, resolution_hz, o));
  }
  return bands;
}

// The design damping: mode 1's ζ unless its line is unresolved; then Klipper's 0.1 (printer data)
// or the next resolved mode's ζ.
std::pair<double, std::string> design_damping(const std::vector<ModeEstimate>& modes, const RecommendOptions& o, bool printer,
                                              double resolution_hz) {
  if (o.design_damping) return {*o.design_damping, "the caller's design damping"};
  const ModeEstimate& m1 = modes.front();
  if (!unresolved(m1, resolution_hz, o)) return {m1.damping_ratio, "mode 1's ζ"};
  const std::string why = line_text(m1, 0, resolution_hz);
  if (printer) return {0.1, why + ": Klipper's design damping 0.1"};
  for (std::size_t i = 1; i < modes.size(); ++i) {
    if (!unresolved(modes[i], resolution_hz, o)) return {modes[i].damping_ratio, fmt::format("{}: mode {}'s ζ, the next resolved line", why, i + 1)};
  }
  return {m1.damping_ratio, why + ", and no other line is resolved: its own ζ"};
}

void validate(const std::vector<MeasuredSpectrum>& spectra, const std::vector<ModeEstimate>& modes, const RecommendOptions& o) {
  if (spectra.empty()) throw InvalidArgument("recommend: no spectra");
  if (modes.empty()) throw InvalidArgument("recommend: no modes");
  for (const auto& m : modes) {
    require_positive("mode frequency_hz", m.frequency_hz);
    require_in_half_open("mode damping_ratio", m.damping_ratio, 0.0, 1.0);
  }
  for (const double z : o.test_damping_ratios) require_in_half_open("test damping ratio", z, 0.0, 1.0);
  if (o.design_damping) require_in_half_open("design damping", *o.design_damping, 0.0, 1.0);
  require_non_negative("frequency_sigmas", o.frequency_sigmas);
  require_in_open("threshold_fraction", o.threshold_fraction, 0.0, 1.0);
  require_in_open("vtol", o.vtol, 0.0, 1.0);
  if (!(o.max_delay_s > 0.0)) throw_invalid("max_delay_s", o.max_delay_s, "> 0 s (infinity: no budget)");
  require_non_negative("vibration_tolerance", o.vibration_tolerance);
  if (o.scan_step_hz) require_positive("scan_step_hz", *o.scan_step_hz);
  require_in_open("scan_step_ratio", o.scan_step_ratio, 0.0, 1.0);
  require_in_closed("max_remaining", o.max_remaining, 0.0, 1.0, "The fraction of the vibration a pick may leave unflagged (0.2 = 20 %).");
  if (!(o.scan_ratio_low > 0.0 && o.scan_ratio_high > o.scan_ratio_low)) {
    throw InvalidArgument(fmt::format("scan ratios [{}, {}]: need 0 < low < high", o.scan_ratio_low, o.scan_ratio_high));
  }
  for (const double f : o.scan_frequencies_hz) require_positive("scan frequency", f);
  require_non_negative("update_grid_hz", o.update_grid_hz, "The drive's update rate in Hz (0: no update grid).");
  require_positive("smoothing acceleration (mm/s²)", o.smoothing.accel_mm_s2);
  require_non_negative("square-corner velocity (mm/s)", o.smoothing.square_corner_velocity_mm_s);
  require_positive("target smoothing (mm)", o.smoothing.target_smoothing_mm);
}

// The shaper as the drive applies it: on its update grid when one is set.
shaping::Shaper applied(const shaping::Shaper& designed, const RecommendOptions& o) {
  return o.update_grid_hz > 0.0 ? shaping::on_update_grid(designed, 1.0 / o.update_grid_hz) : designed;
}

// On an update grid different designs can land on the same impulses: each such candidate names
// the first one listed with them and is not chosen.
void mark_duplicates(std::vector<CandidateResult>& c, double grid_hz) {
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!c[i].available) continue;
    for (std::size_t j = 0; j < i; ++j) {
      if (!c[j].available || c[j].duplicate_of || !same_impulses(*c[i].shaper, *c[j].shaper)) continue;
      c[i].duplicate_of = c[j].name;
      const std::string same = fmt::format("on the {:g} Hz update grid the same impulses as {}", grid_hz, c[j].name);
      c[i].note = c[i].note.empty() ? same : c[i].note + "; " + same;
      break;
    }
  }
}

std::string percent(double v) { return fmt::format("{:.1f} %", 100.0 * v); }
std::string millis(double s) { return fmt::format("{:.1f} ms", 1000.0 * s); }

std::string upper(std::string s) {
  for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return s;
}

void choose(Recommendation& r, const RecommendOptions& o) {
  const auto& c = r.candidates;
  std::optional<std::size_t> least;
  const auto eligible = [&](std::size_t i) { return c[i].available && c[i].within_budget && !c[i].duplicate_of; };
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (eligible(i) && (!least || c[i].remaining_worst < c[*least].remaining_worst)) least = i;
  }
  const bool budget = std::isfinite(o.max_delay_s);
  if (!least) {
    std::optional<std::size_t> shortest;
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (c[i].available && (!shortest || c[i].duration_s < c[*shortest].duration_s)) shortest = i;
    }
    r.reason = shortest ? fmt::format("no candidate fits the delay budget of {}; the shortest, {}, takes {}", millis(o.max_delay_s),
                                      upper(c[*shortest].name), millis(c[*shortest].duration_s))
                        : "no candidate could be designed";
    return;
  }
  const double limit = c[*least].remaining_worst + o.vibration_tolerance;
  std::size_t pick = *least;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!eligible(i) || c[i].remaining_worst > limit) continue;
    if (c[i].duration_s < c[pick].duration_s ||
        (c[i].duration_s == c[pick].duration_s && c[i].remaining_worst < c[pick].remaining_worst)) {
      pick = i;
    }
  }
  r.chosen = pick;
  const auto& p = c[pick];
  const std::string within = budget ? fmt::format(" within the {} delay budget", millis(o.max_delay_s)) : "";
  if (pick == *least) {
    r.reason = fmt::format("{}: least worst-case remaining vibration ({}){}", upper(p.name), percent(p.remaining_worst), within);
  } else {
    r.reason = fmt::format("{}: the shortest candidate ({}) whose worst-case remaining vibration ({}) is within {:.1f} points of the "
                           "least ({}: {} at {} more){}",
                           upper(p.name), millis(p.duration_s), percent(p.remaining_worst), 100.0 * o.vibration_tolerance,
                           upper(c[*least].name), percent(c[*least].remaining_worst),
                           millis(c[*least].duration_s - p.duration_s), within);
  }
  // The next shorter candidate that was passed over, and why.
  std::optional<std::size_t> shorter;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!eligible(i) || c[i].duration_s >= p.duration_s) continue;
    if (!shorter || c[i].duration_s > c[*shorter].duration_s) shorter = i;
  }
  if (shorter) {
    r.reason += fmt::format("; {} leaves {} at {} less", upper(c[*shorter].name), percent(c[*shorter].remaining_worst),
                            millis(p.duration_s - c[*shorter].duration_s));
  }
  if (p.leaves_too_much) {
    r.warning = fmt::format("{} leaves {} of the vibration (more than the {} limit): no candidate cancels what this spectrum holds "
                            "(more modes than the candidates cover, or a forced response rather than a resonance); record the free "
                            "decay after a move (--from-s after it) or a response to broadband excitation",
                            upper(p.name), percent(p.remaining_worst), percent(o.max_remaining));
  }
}

// Every figure of a candidate whose shaper is set: remaining vibration, delay, printer figures.
void evaluate(CandidateResult& c, const Evaluator& ev, const RecommendOptions& o) {
  c.remaining_worst = ev.worst(*c.shaper);
  c.remaining_nominal = ev.nominal(*c.shaper);
  if (c.designed) c.remaining_worst_designed = ev.worst(*c.designed);
  c.duration_s = c.shaper->duration_s();
  c.within_budget = c.duration_s <= o.max_delay_s * (1.0 + 1e-12);
  c.leaves_too_much = c.remaining_worst > o.max_remaining;
  c.smoothing_mm = ev.smoothing(*c.shaper);
  c.max_accel_mm_s2 = max_accel_mm_s2(*c.shaper, o.smoothing.square_corner_velocity_mm_s, o.smoothing.target_smoothing_mm);
  c.klipper_score = klipper_score(c.smoothing_mm, c.remaining_worst);
}

// A candidate's frequency scan, kept for Klipper's choice (single-mode candidates only), and the
// candidate as a function of each design frequency (a convolution's other factor held at its fit).
struct ScanFit {
  std::vector<ScanPoint> points;
  std::vector<std::function<shaping::Shaper(double)>> factors;
};

// Klipper's choice across candidates, in their order (shaper_calibrate.py, find_best_shaper).
std::size_t klipper_best(std::vector<CandidateResult>& c, const std::vector<ScanFit>& fits, const Evaluator& ev,
                         const RecommendOptions& o) {
  const auto usable = [&](std::size_t i) { return c[i].available && c[i].within_budget && !c[i].duplicate_of; };
  // Klipper's score trades vibration for smoothing without a bound: a short shaper leaving more than
  // max_remaining can out-score one that cancels the spectrum. It competes only when all do.
  const bool some_enough = std::any_of(c.begin(), c.end(), [&](const CandidateResult& x) { return x.available && x.within_budget && !x.duplicate_of && !x.leaves_too_much; });
  const auto eligible = [&](std::size_t i) { return usable(i) && (!some_enough || !c[i].leaves_too_much); };
  std::optional<std::size_t> best;
  for (std::size_t i = 0; i < c.size(); ++i) {
    if (!eligible(i)) continue;
    if (!best || c[i].klipper_score * 1.2 < c[*best].klipper_score ||
        (c[i].klipper_score * 1.05 < c[*best].klipper_score && c[i].smoothing_mm * 1.1 < c[*best].smoothing_mm)) {
      best = i;
    }
    // A scan point with less vibration and less smoothing than the best so far replaces it.
    for (const auto& p : fits[i].points) {
      if (!(p.remaining < c[*best].remaining_worst && p.smoothing_mm < c[*best].smoothing_mm)) continue;
      CandidateResult moved = c[i];
      moved.design_frequency_hz = {p.frequency_hz};
      moved.shaper = fits[i].factors.front()(p.frequency_hz);
      evaluate(moved, ev, o);
      if (!moved.within_budget) continue;
      c[i] = std::move(moved);
      best = i;
    }
  }
  if (c[*best].name == "zv") {  // a ZV pick gives way to the first candidate leaving 10 % less
    for (std::size_t i = 0; i < c.size(); ++i) {
      if (eligible(i) && c[i].name != "zv" && c[i].remaining_worst * 1.1 < c[*best].remaining_worst) return i;
    }
  }
  return *best;
}

void choose_as_klipper(Recommendation& r, const std::vector<ScanFit>& fits, const Evaluator& ev, const RecommendOptions& o) {
  const CandidateResult by_delay = r.candidates[*r.chosen];
  const std::size_t pick = klipper_best(r.candidates, fits, ev, o);
  r.chosen = pick;
  r.weighed_smoothing = true;
  const auto& p = r.candidates[pick];
  const std::string delay_rule = by_delay.name == p.name
                                     ? fmt::format("the delay rule picks {} too", upper(p.name))
                                     : fmt::format("the delay rule would pick {} ({}, smoothing {:.3f} mm, {})", upper(by_delay.name),
                                                   percent(by_delay.remaining_worst), by_delay.smoothing_mm, millis(by_delay.duration_s));
  r.reason = fmt::format("{}: Klipper's pick, the best score smoothing·(v^1.5 + 0.2v + 0.01) = {:.3g} (remaining {}, smoothing "
                         "{:.3f} mm at {:g} mm/s², max accel {:.0f} mm/s², {}); {}",
                         upper(p.name), p.klipper_score, percent(p.remaining_worst), p.smoothing_mm, o.smoothing.accel_mm_s2,
                         p.max_accel_mm_s2, millis(p.duration_s), delay_rule);
  r.warning.clear();
  if (p.leaves_too_much) {
    r.warning = fmt::format("{} leaves {} of the vibration (more than the {} limit): no candidate cancels what this spectrum holds; "
                            "record the response to broadband excitation again", upper(p.name), percent(p.remaining_worst),
                            percent(o.max_remaining));
  }
}

// The parts of a design frequency's offset from its mode, largest first, as one line.
std::string offset_reason(const DesignOffset& d, const Recommendation& r, const RecommendOptions& o, const std::string& label) {
  const auto [lo, hi] = std::minmax_element(r.test_damping_ratios.begin(), r.test_damping_ratios.end());
  std::string other;
  for (const auto& m : r.modes) {
    if (m.frequency_hz != d.mode_frequency_hz) other = fmt::format("another mode at {:.4g} Hz", m.frequency_hz);
  }
  const std::string uncertainty = r.frequency_scales.size() > 1 ? fmt::format(" and the mode's frequency ± {:g}σ", o.frequency_sigmas) : "";
  const std::string selection = o.weigh_smoothing        ? "for Klipper's lowest score (smoothing) among the near-best frequencies"
                                : o.update_grid_hz > 0.0 ? fmt::format("on the {:g} Hz update grid", o.update_grid_hz)
                                                         : "for the joint fit of the convolution's two factors";
  std::vector<std::pair<double, std::string>> parts{
      {d.spectrum_hz, fmt::format("where the spectrum itself leaves least (ζ {:.3g}, no uncertainty: {})", r.design_damping,
                                  other.empty() ? "its power above the threshold is not centred on the mode's line" : other)},
      {d.near_best_hz, fmt::format("for the shortest shaper within {:g} × the least + {:g} points", o.near_best_factor,
                                   100.0 * o.near_best_offset)},
      {d.worst_case_hz, fmt::format("for the worst case over ζ {:.3g}–{:.3g}{}", *lo, *hi, uncertainty)},
      {d.selection_hz, selection}};
  std::stable_sort(parts.begin(), parts.end(), [](const auto& a, const auto& b) { return std::abs(a.first) > std::abs(b.first); });
  std::string line = fmt::format("{} at {:.4g} Hz is {:.2f}σ {} the mode at {:.4g} ± {:.2g} Hz:", label, d.design_frequency_hz,
                                 std::abs(d.offset_sigmas), d.offset_sigmas > 0.0 ? "above" : "below", d.mode_frequency_hz,
                                 d.mode_frequency_std_hz);
  const char* sep = " ";
  for (const auto& [hz, why] : parts) {
    if (std::abs(hz) < 0.1 * d.mode_frequency_std_hz) continue;  // a part under 0.1σ explains nothing
    line += fmt::format("{}{:+.3g} Hz {}", sep, hz, why);
    sep = "; ";
  }
  return line;
}

// The mode a design frequency is compared with: a convolution factor's own, else the nearest.
const ModeEstimate& mode_of(const Recommendation& r, std::size_t factor, std::size_t factors, double design_hz) {
  if (factors > 1 && factor < r.modes.size()) return r.modes[factor];
  return *std::min_element(r.modes.begin(), r.modes.end(), [&](const ModeEstimate& a, const ModeEstimate& b) {
    return std::abs(a.frequency_hz - design_hz) < std::abs(b.frequency_hz - design_hz);
  });
}

// Each design frequency of the chosen candidate more than 1σ from its mode, its offset split by
// re-scanning with the delay rule's frequency choice (scan()): the least at the design ζ alone
// (the spectrum), the shortest near-best there, the same on the worst case, and the design itself.
std::vector<DesignOffset> design_offsets(const Recommendation& r, const ScanFit& fit, const Evaluator& ev, const RecommendOptions& o) {
  const CandidateResult& c = r.candidates[*r.chosen];
  DampingBand design;
  design.high_hz = std::numeric_limits<double>::infinity();
  design.ratios = {r.design_damping};
  const Evaluator nominal = make_evaluator(ev.bins, {design}, {1.0}, ev.printer);
  RecommendOptions plain = o;
  plain.weigh_smoothing = false;
  std::vector<DesignOffset> out;
  const std::size_t n = std::min(c.design_frequency_hz.size(), fit.factors.size());
  for (std::size_t i = 0; i < n; ++i) {
    DesignOffset d;
    d.factor = i;
    d.design_frequency_hz = c.design_frequency_hz[i];
    const ModeEstimate& mode = mode_of(r, i, n, d.design_frequency_hz);
    d.mode_frequency_hz = mode.frequency_hz;
    d.mode_frequency_std_hz = mode.frequency_std_hz;
    const double offset = d.design_frequency_hz - d.mode_frequency_hz;
    if (!(std::abs(offset) > d.mode_frequency_std_hz)) continue;
    d.offset_sigmas = d.mode_frequency_std_hz > 0.0 ? offset / d.mode_frequency_std_hz : std::copysign(HUGE_VAL, offset);
    const std::vector<double> grid = scan_grid(o, r.modes[std::min(i, r.modes.size() - 1)].frequency_hz);
    const ScanResult at_design = scan(grid, fit.factors[i], nominal, plain, d.mode_frequency_hz);
    const ScanResult worst = scan(grid, fit.factors[i], ev, plain, d.mode_frequency_hz);
    d.spectrum_hz = at_design.least_hz - d.mode_frequency_hz;
    d.near_best_hz = at_design.selected_hz - at_design.least_hz;
    d.worst_case_hz = worst.selected_hz - at_design.selected_hz;
    d.selection_hz = d.design_frequency_hz - worst.selected_hz;
    const double parts[4] = {std::abs(d.spectrum_hz), std::abs(d.near_best_hz), std::abs(d.worst_case_hz), std::abs(d.selection_hz)};
    static const char* const kCauses[4] = {"spectrum", "near_best", "worst_case", "selection"};
    const auto largest = std::max_element(parts, parts + 4) - parts;
    d.cause = largest == 0 && r.modes.size() > 1 ? "second_mode" : kCauses[largest];
    d.reason = offset_reason(d, r, o, upper(c.name) + (n > 1 ? fmt::format(" (factor {})", i + 1) : ""));
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace

std::vector<std::string> default_candidates(std::size_t modes) {
  std::vector<std::string> c = kSingle;
  if (modes >= 2) {
    for (const char* n : {"zv*zv", "mzv*mzv", "zvd*zvd", "ei*ei"}) c.emplace_back(n);
  }
  return c;
}

Recommendation recommend(const std::vector<MeasuredSpectrum>& spectra, const std::vector<ModeEstimate>& modes,
                         const RecommendOptions& o) {
  validate(spectra, modes, o);
  Recommendation r;
  r.modes = modes;
  const ModeEstimate& m1 = modes.front();
  const bool printer = std::any_of(spectra.begin(), spectra.end(), [](const MeasuredSpectrum& s) { return s.format != InputFormat::table; });
  const double resolution_hz = spectra.front().resolution_hz;
  const auto [design_zeta, design_why] = design_damping(modes, o, printer, resolution_hz);
  r.design_damping = std::clamp(design_zeta, 0.0, 0.9);
  r.design_damping_reason = design_why;
  r.damping_bands = damping_bands(modes, o, r.design_damping, printer, resolution_hz);
  r.test_damping_ratios = r.damping_bands.front().ratios;
  double u = 0.0;
  for (const auto& m : modes) u = std::max(u, o.frequency_sigmas * m.frequency_std_hz / m.frequency_hz);
  u = std::min(u, 0.3);
  r.frequency_scales = u > 0.0 ? std::vector<double>{1.0 - u, 1.0, 1.0 + u} : std::vector<double>{1.0};
  const double si_half_band = std::clamp(u, o.si_min_half_band, 0.3);

  std::vector<WeightedBins> bins;
  for (const auto& s : spectra) {
    const double min_f = o.min_frequency_hz ? *o.min_frequency_hz : 2.0 * s.resolution_hz;
    bins.push_back(weighted_bins(scored_spectrum(s), o.threshold_fraction, min_f));
    r.klipper_normalized = r.klipper_normalized || s.klipper_normalizes;
  }
  const Evaluator ev = make_evaluator(bins, r.damping_bands, r.frequency_scales, o.smoothing);

  const std::vector<std::string> names = o.candidates.empty() ? default_candidates(modes.size()) : o.candidates;
  r.printer_figures = o.weigh_smoothing || printer;
  std::vector<ScanFit> fits;
  for (const std::string& name : names) {
    CandidateResult c;
    ScanFit fit;
    c.name = name;
    c.design_damping = r.design_damping;
    const auto star = name.find('*');
    const std::string a = name.substr(0, star);
    const std::string b = star == std::string::npos ? std::string() : name.substr(star + 1);
    if (!is_single(a) || (star != std::string::npos && (!is_single(b) || a == "si" || b == "si"))) {
      throw InvalidArgument(fmt::format("candidate '{}' is unknown; allowed: {} and two-mode a*b of those (not si)", name,
                                        fmt::join(kSingle, ", ")));
    }
    if (star != std::string::npos && modes.size() < 2) {
      throw InvalidArgument(fmt::format("candidate '{}' needs two modes; one was found", name));
    }
    try {
      const shaping::Shaper p1 = prototype(a, r.design_damping, o, si_half_band);
      if (star == std::string::npos) {
        const auto make = [&](double f) { return applied(scaled(p1, f), o); };
        const ScanResult s = scan(scan_grid(o, m1.frequency_hz), make, ev, o, m1.frequency_hz);
        c.design_frequency_hz = {s.selected_hz};
        c.least_remaining = s.least_v;
        c.least_remaining_frequency_hz = s.least_hz;
        c.shaper = make(s.selected_hz);
        if (o.update_grid_hz > 0.0) c.designed = scaled(p1, s.selected_hz);
        fit.points = s.points;
        fit.factors = {[p1, &o](double f) { return applied(scaled(p1, f), o); }};
      } else {
        const ModeEstimate& m2 = modes[1];
        // An unresolved second line of printer data: Klipper's design damping too (design_damping()).
        const double zeta2 = std::clamp(printer && unresolved(m2, resolution_hz, o) ? 0.1 : m2.damping_ratio, 0.0, 0.9);
        const shaping::Shaper p2 = prototype(b, zeta2, o, si_half_band);
        double f1 = m1.frequency_hz, f2 = m2.frequency_hz;
        ScanResult s;
        // Coordinate descent: the first factor's frequency, the second's, the first's again.
        for (int pass = 0; pass < 3; ++pass) {
          if (pass % 2 == 0) {
            s = scan(scan_grid(o, m1.frequency_hz), [&](double f) { return applied(shaping::convolve(scaled(p1, f), scaled(p2, f2)), o); }, ev, o,
                     m1.frequency_hz);
            f1 = s.selected_hz;
            c.least_remaining = s.least_v;
            c.least_remaining_frequency_hz = s.least_hz;
          } else {
            s = scan(scan_grid(o, m2.frequency_hz), [&](double f) { return applied(shaping::convolve(scaled(p1, f1), scaled(p2, f)), o); }, ev, o,
                     m2.frequency_hz);
            f2 = s.selected_hz;
          }
        }
        c.design_frequency_hz = {f1, f2};
        c.shaper = applied(shaping::convolve(scaled(p1, f1), scaled(p2, f2)), o);
        if (o.update_grid_hz > 0.0) c.designed = shaping::convolve(scaled(p1, f1), scaled(p2, f2));
        c.note = fmt::format("second factor designed at ζ = {:.4g}", zeta2);
        fit.factors = {[p1, p2, f2, &o](double f) { return applied(shaping::convolve(scaled(p1, f), scaled(p2, f2)), o); },
                       [p1, p2, f1, &o](double f) { return applied(shaping::convolve(scaled(p1, f1), scaled(p2, f)), o); }};
      }
      evaluate(c, ev, o);
    } catch (const InvalidArgument& e) {
      c.available = false;
      c.note = e.what();
    } catch (const RuntimeError& e) {
      c.available = false;
      c.note = e.what();
    }
    r.candidates.push_back(std::move(c));
    fits.push_back(std::move(fit));
  }
  if (o.update_grid_hz > 0.0) mark_duplicates(r.candidates, o.update_grid_hz);
  choose(r, o);
  if (o.weigh_smoothing && r.chosen) choose_as_klipper(r, fits, ev, o);
  if (r.chosen) r.design_offsets = design_offsets(r, fits[*r.chosen], ev, o);
  return r;
}

const std::vector<double>& damping_ratios_at(const Recommendation& r, double frequency_hz) {
  if (r.damping_bands.empty()) return r.test_damping_ratios;
  return band_at(r.damping_bands, frequency_hz).ratios;
}

std::vector<double> worst_response(const shaping::Shaper& shaper, const std::vector<double>& frequency_hz, const Recommendation& r) {
  std::vector<double> out;
  for (const double f : frequency_hz) out.push_back(advise::worst_response(shaper, {f}, damping_ratios_at(r, f), r.frequency_scales).front());
  return out;
}

std::vector<double> power_after_shaper(const shaping::Shaper& shaper, const std::vector<double>& frequency_hz,
                                       const std::vector<double>& power, const Recommendation& r) {
  if (power.size() != frequency_hz.size()) {
    throw InvalidArgument(fmt::format("power_after_shaper: {} powers for {} frequencies", power.size(), frequency_hz.size()));
  }
  std::vector<double> out = worst_response(shaper, frequency_hz, r);
  for (std::size_t k = 0; k < out.size(); ++k) out[k] = power[k] * out[k] * out[k];  // |residual/unshaped|² of power
  return out;
}

}  // namespace clearshape::advise
