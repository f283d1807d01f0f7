#pragma once
// Recommending an input shaper from a measured spectrum (docs/recommend.md), after Klipper's
// calibrate_shaper and beyond it: every candidate (ZV … EI3, SI over the mode's uncertainty
// band, two-mode convolutions) has its design frequency fitted to the spectrum by a scan that
// minimises the worst-case remaining vibration (remaining.hpp); the recommendation is the
// shortest candidate whose worst-case remaining vibration is within a tolerance of the least,
// inside an optional delay budget.
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "clearshape/advise/mode_estimate.hpp"
#include "clearshape/advise/remaining.hpp"
#include "clearshape/advise/smoothing.hpp"
#include "clearshape/shaping/shaper.hpp"

namespace clearshape::advise {

/// Candidate names: zv mzv zvd zvdd zvddd ei ei2 ei3 si (one mode) and zv*zv mzv*mzv zvd*zvd
/// ei*ei (two modes).
std::vector<std::string> default_candidates(std::size_t modes);

struct RecommendOptions {
  std::vector<std::string> candidates;        ///< empty: default_candidates(modes)
  /// Default: the first mode's ζ; when its line is unresolved (unresolved_bins), Klipper's 0.1 for
  /// printer data, else the next resolved mode's ζ (Recommendation::design_damping_reason says which).
  std::optional<double> design_damping;
  /// Test damping ratios; empty: damping_points ratios evenly over [damping_low, damping_high],
  /// and without those the mode's ζ ± max(2σ, ζ/4) (clipped to [0.001, 0.9]). Any of these
  /// options holds every bin to the one band (no per-line bands).
  std::vector<double> test_damping_ratios;
  std::optional<double> damping_low, damping_high;
  std::size_t damping_points = 3;
  /// A spectral mode whose half-power width 2ζf is at most this many bins (the first spectrum's
  /// resolution) is unresolved: its ζ is no design damping, and its own bins are tested over its
  /// band while the rest of the spectrum is tested without it (Recommendation::damping_bands).
  /// 0: off (one band for every bin, the first mode's ζ).
  double unresolved_bins = 2.0;
  /// Frequency uncertainty: scales 1 − k·σ_f/f, 1, 1 + k·σ_f/f with k = frequency_sigmas (0: none).
  double frequency_sigmas = 2.0;
  double si_min_half_band = 0.02;             ///< SI band half-width ≥ this fraction of f
  /// Scan grid: explicit frequencies, or ratio_low·f … ratio_high·f, each point (1 + step_ratio)
  /// × the one before (log-spaced, so the design does not depend on the unit of time: 0.005 gives
  /// 197 points over 0.6–1.6 × f); scan_step_hz instead gives a linear grid in steps of that many
  /// Hz (at most 200 points; tied to the time unit).
  std::vector<double> scan_frequencies_hz;
  double scan_ratio_low = 0.6, scan_ratio_high = 1.6, scan_step_ratio = 0.005;
  std::optional<double> scan_step_hz;
  /// Klipper's frequency choice: among scan points with remaining < factor·least + offset, the
  /// shortest shaper (highest design frequency) is fitted.
  double near_best_factor = 1.1, near_best_offset = 0.0005;
  double threshold_fraction = 0.05;           ///< PSD threshold (Klipper: 1/20 of the max)
  std::optional<double> min_frequency_hz;     ///< bins below are ignored; default 2 × resolution
  double vtol = 0.05;                         ///< EI/SI tolerance
  double max_delay_s = std::numeric_limits<double>::infinity();  ///< delay budget
  double vibration_tolerance = 0.01;          ///< "within 1 percentage point of the least"
  /// A candidate whose worst-case remaining vibration exceeds this fraction is flagged
  /// (CandidateResult::leaves_too_much); when the pick is such a one, Recommendation::warning says so.
  double max_remaining = 0.2;
  /// > 0: the drive takes a new command only at updates of this rate (Hz), so every candidate is
  /// snapped to that grid (shaping::on_update_grid) before anything is evaluated — the frequency
  /// scan included: remaining vibration, duration and the choice are those of the applied
  /// shaper. 0: off (the designed shapers as they are).
  double update_grid_hz = 0.0;
  /// Printer figures (smoothing.hpp): every candidate's smoothing at smoothing.accel_mm_s2 and its
  /// max acceleration are always computed. weigh_smoothing: pick as Klipper's calibrate_shaper
  /// does — each candidate's frequency is the lowest klipper_score among the near-best scan
  /// points (instead of the highest frequency), and the candidates are compared in order by
  /// Klipper's rules (a later one wins with a 20 % lower score, or 5 % lower with 10 % less
  /// smoothing; a scan point with less vibration and less smoothing than the pick replaces it; a
  /// ZV pick gives way to the first candidate leaving 10 % less). The vibration v in the score is
  /// the worst-case remaining vibration.
  SmoothingSettings smoothing;
  bool weigh_smoothing = false;
};

struct CandidateResult {
  std::string name;
  bool available = true;
  std::string note;                            ///< why not available, or a remark
  std::vector<double> design_frequency_hz;     ///< fitted (one per mode of the candidate)
  double design_damping = 0.0;
  double remaining_worst = 0.0;                ///< at the fitted frequency: worst over ζ and scales
  double remaining_nominal = 0.0;              ///< … worst over ζ, scale 1 only
  double least_remaining = 0.0;                ///< the scan's least worst-case remaining …
  double least_remaining_frequency_hz = 0.0;   ///< … and where (first mode's frequency)
  double duration_s = 0.0;                     ///< the delay it adds
  bool within_budget = true;
  bool leaves_too_much = false;                ///< remaining_worst > RecommendOptions::max_remaining
  std::optional<shaping::Shaper> shaper;       ///< as applied (on the update grid when one is set)
  /// With an update grid only: the off-grid design at design_frequency_hz and its worst-case
  /// remaining vibration (what the grid costs), and the earlier candidate whose applied
  /// impulses are the same (times equal, amplitudes within 1e-9): such a duplicate is listed
  /// but never chosen.
  std::optional<shaping::Shaper> designed;
  double remaining_worst_designed = 0.0;
  std::optional<std::string> duplicate_of;
  double smoothing_mm = 0.0;                   ///< Klipper's smoothing at RecommendOptions::smoothing
  double max_accel_mm_s2 = 0.0;                ///< … and the acceleration keeping it under the target
  double klipper_score = 0.0;                  ///< smoothing_mm · (v^1.5 + 0.2 v + 0.01), v = remaining_worst
};

/// Why a design frequency of the recommended candidate sits more than 1σ from its mode (the
/// nearest mode; a convolution's factor: the mode it is designed for) (docs/recommend.md, "Why a
/// design frequency sits away from the mode"). The offset is split in four by re-scanning the
/// candidate's frequency (a convolution's other factor held at its fit):
/// design − mode = spectrum_hz + near_best_hz + worst_case_hz + selection_hz.
struct DesignOffset {
  std::size_t factor = 0;               ///< which design frequency (1: a convolution's second factor)
  double design_frequency_hz = 0.0;
  double mode_frequency_hz = 0.0, mode_frequency_std_hz = 0.0;
  double offset_sigmas = 0.0;           ///< (design − mode) / σ
  double spectrum_hz = 0.0;     ///< the least on the spectrum at the design ζ, scale 1 only, − the mode
  double near_best_hz = 0.0;    ///< the shortest near-best frequency there − that least
  double worst_case_hz = 0.0;   ///< the same rule on the worst case over the test ζ and scales − that
  double selection_hz = 0.0;    ///< the design − that: Klipper's score, the update grid, a convolution's joint fit
  std::string cause;  ///< the largest part: "spectrum" ("second_mode" with two modes), "near_best", "worst_case", "selection"
  std::string reason;           ///< one line, for the figure and the JSON
};

/// The damping ratios a group of bins is tested over (docs/recommend.md, "Per-line damping bands").
struct DampingBand {
  double low_hz = 0.0, high_hz = 0.0;     ///< the bins it holds; the rest band: 0 … ∞ (every bin no other holds)
  std::vector<double> ratios;
  std::optional<std::size_t> mode;        ///< the unresolved mode (index into modes) whose line it is; none: the rest
  std::string reason;                     ///< one line: where the band comes from
};

struct Recommendation {
  std::vector<ModeEstimate> modes;
  std::vector<double> test_damping_ratios;    ///< the rest band's (damping_bands.front())
  /// The rest band first (every bin no other band holds), then one band per unresolved line.
  std::vector<DampingBand> damping_bands;
  std::vector<double> frequency_scales;
  double design_damping = 0.0;
  std::string design_damping_reason;          ///< one line: whose ζ, and why
  std::vector<CandidateResult> candidates;
  std::optional<std::size_t> chosen;          ///< index into candidates
  std::string reason;
  std::string warning;                        ///< non-empty: the pick leaves more than max_remaining
  std::vector<DesignOffset> design_offsets;   ///< the chosen candidate's frequencies > 1σ off their mode
  bool weighed_smoothing = false;             ///< the pick followed Klipper's score (weigh_smoothing)
  /// Printer data (a Klipper file among the spectra) or weigh_smoothing: the output shows the
  /// candidates' smoothing and max acceleration.
  bool printer_figures = false;
  /// A spectrum was scored as Klipper scores it, its PSD ÷ (f + 0.1 Hz) (scored_spectrum: a Klipper
  /// TEST_RESONANCES file Klipper normalises); the modes were found on the PSD as measured.
  bool klipper_normalized = false;
};

/// Throws InvalidArgument for no spectra, no modes, an unknown candidate, a two-mode candidate
/// with one mode, or an option out of range (update_grid_hz: finite and >= 0).
Recommendation recommend(const std::vector<MeasuredSpectrum>& spectra, const std::vector<ModeEstimate>& modes,
                         const RecommendOptions& options = {});

/// The test damping ratios of the band holding a bin at frequency_hz (the rest band's when none other does).
const std::vector<double>& damping_ratios_at(const Recommendation& r, double frequency_hz);

/// worst_response and power_after_shaper (remaining.hpp) with each frequency's own band (damping_ratios_at).
std::vector<double> worst_response(const shaping::Shaper& shaper, const std::vector<double>& frequency_hz, const Recommendation& r);
std::vector<double> power_after_shaper(const shaping::Shaper& shaper, const std::vector<double>& frequency_hz,
                                       const std::vector<double>& power, const Recommendation& r);

}  // namespace clearshape::advise
