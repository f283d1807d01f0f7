#include "clearshape/metrics/mean_deviation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "clearshape/core/error.hpp"
#include "validate.hpp"

namespace clearshape::metrics {
namespace {

double mean_from(std::span<const double> s, std::size_t first) {
  double sum = 0.0;
  for (std::size_t i = first; i < s.size(); ++i) sum += s[i];
  return sum / static_cast<double>(s.size() - first);
}

// Noise floor from the mean square successive difference (von Neumann et al. 1941):
// σ² = Σ (s_{i+1} − s_i)² / (2 (n − 1)).
double successive_difference_sigma(std::span<const double> s, std::size_t first) {
  const std::size_t n = s.size() - first;
  if (n < 2) return 0.0;
  double sum_sq = 0.0;
  for (std::size_t i = first + 1; i < s.size(); ++i) sum_sq += (s[i] - s[i - 1]) * (s[i] - s[i - 1]);
  return std::sqrt(sum_sq / (2.0 * static_cast<double>(n - 1)));
}

struct Meeting {
  std::size_t index = 0;
  StartRule rule = StartRule::crossing;
};

// Departure (header step 2): the first index j >= from at which |s_j − M| reaches half the
// largest |s_i − M|, i >= from; s.size() when the response never leaves M.
std::size_t departure(std::span<const double> s, std::size_t from, double m) {
  double largest = 0.0;
  for (std::size_t i = from; i < s.size(); ++i) largest = std::max(largest, std::abs(s[i] - m));
  if (!(largest > 0.0)) return s.size();
  for (std::size_t i = from; i < s.size(); ++i) {
    if (std::abs(s[i] - m) >= 0.5 * largest) return i;
  }
  return s.size();
}

// First index i > from where s_i == M or s_i − M changes sign with respect to s_{i−1} − M
// (the thesis's "first coincide point", §5.1.2); `from` is the departure.
std::optional<std::size_t> first_crossing(std::span<const double> s, std::size_t from, double m) {
  for (std::size_t i = from; i < s.size(); ++i) {
    const double d = s[i] - m;
    if (d == 0.0) return i;
    if (i > from) {
      const double previous = s[i - 1] - m;
      if ((previous < 0.0 && d > 0.0) || (previous > 0.0 && d < 0.0)) return i;
    }
  }
  return std::nullopt;
}

// First index r in [from, before) that starts a stay inside |s − M| <= band of `dwell` samples
// or one that lasts to the end of the record.
std::optional<std::size_t> first_band_entry(std::span<const double> s, std::size_t from,
                                            std::size_t before, double m, double band,
                                            std::size_t dwell) {
  if (!(band > 0.0)) return std::nullopt;
  std::optional<std::size_t> run_start;
  for (std::size_t i = from; i < s.size(); ++i) {
    if (std::abs(s[i] - m) <= band) {
      if (!run_start) {
        if (i >= before) return std::nullopt;
        run_start = i;
      }
      if (i + 1 - *run_start >= dwell) return run_start;
    } else {
      run_start.reset();
    }
  }
  return run_start;  // inside the band to the end of the record
}

// The start k(M) of header step 2: after the departure, the earlier of the first crossing and
// the first band entry (a tie counts as a crossing).
std::optional<Meeting> first_meeting(std::span<const double> s, std::size_t search_from, double m,
                                     double band, std::size_t dwell) {
  const std::size_t from = departure(s, search_from, m);
  if (from >= s.size()) return std::nullopt;
  const auto crossing = first_crossing(s, from, m);
  const auto entry = first_band_entry(s, from, crossing.value_or(s.size()), m, band, dwell);
  if (entry) return Meeting{*entry, StartRule::band_entry};
  if (crossing) return Meeting{*crossing, StartRule::crossing};
  return std::nullopt;
}

}  // namespace

std::string_view to_string(StartRule rule) noexcept {
  switch (rule) {
    case StartRule::crossing: return "crossing";
    case StartRule::band_entry: return "band-entry";
    case StartRule::window_start: return "window-start";
  }
  return "crossing";
}

MeanDeviationResult mean_deviation(const UniformSeries& response,
                                   const MeanDeviationOptions& options) {
  const std::span<const double> s = response.values;
  detail::require_min_size("response", s.size(), 2);
  detail::require_finite_samples("response", s);
  require_positive("sample_time_s", response.sample_time_s);
  require_in_closed("final_window_fraction", options.final_window_fraction, 1e-12, 1.0,
                    "Use a share of the record such as 0.2");
  if (options.max_iterations < 1) {
    throw_invalid("max_iterations", options.max_iterations, ">= 1");
  }
  if (std::isnan(options.search_from_s) || options.search_from_s > response.end_s()) {
    throw_invalid("search_from_s", options.search_from_s,
                  "<= the last sample time " + std::to_string(response.end_s()) + " s",
                  "Search for the steady state inside the record");
  }
  require_non_negative("band_noise_multiple", options.band_noise_multiple,
                       "Use 0 (the default) or about 3 for records that never cross their mean");
  require_in_half_open("band_move_fraction", options.band_move_fraction, 0.0, 1.0,
                       "Use a small share of the move such as 0.005");
  require_non_negative("band_dwell_s", options.band_dwell_s, "Use a dwell such as 0.1 s");
  if (!std::isnan(options.band_half_width)) {
    require_non_negative("band_half_width", options.band_half_width,
                         "Leave it NaN to compute it, or give 0 for the crossing rule alone");
  }

  const std::size_t n_total = s.size();
  std::size_t from = 0;
  if (options.search_from_s > response.start_s) {
    from = static_cast<std::size_t>(
        std::ceil((options.search_from_s - response.start_s) / response.sample_time_s - 1e-9));
    from = std::min(from, n_total - 1);
  }
  const auto window = static_cast<std::size_t>(
      std::ceil(options.final_window_fraction * static_cast<double>(n_total)));
  const std::size_t window_start = std::max(from, n_total - std::clamp<std::size_t>(window, 1, n_total));

  MeanDeviationResult result;
  double m = mean_from(s, window_start);  // M₀: mean of the final window
  result.noise_floor = successive_difference_sigma(s, window_start);
  result.band_half_width =
      std::isnan(options.band_half_width)
          ? std::max(options.band_noise_multiple * result.noise_floor,
                     options.band_move_fraction * std::abs(m - s[from]))
          : options.band_half_width;
  const double band = result.band_half_width;
  const std::size_t dwell = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::llround(options.band_dwell_s / response.sample_time_s)));

  std::vector<std::size_t> visited;
  Meeting k{window_start, StartRule::window_start};
  if (const auto meet = first_meeting(s, from, m, band, dwell)) k = *meet;
  visited.push_back(k.index);
  for (int it = 1; it <= options.max_iterations; ++it) {
    result.iterations = it;
    m = mean_from(s, k.index);  // M = mean of the steady-state part
    const Meeting next = first_meeting(s, from, m, band, dwell).value_or(k);
    if (next.index == k.index) {
      k = next;
      result.converged = true;
      break;
    }
    if (std::find(visited.begin(), visited.end(), next.index) != visited.end()) {
      k = next;
      m = mean_from(s, k.index);
      break;  // a cycle: converged stays false
    }
    k = next;
    visited.push_back(k.index);
    if (it == options.max_iterations) m = mean_from(s, k.index);
  }

  double sum_sq = 0.0;
  for (std::size_t i = k.index; i < n_total; ++i) {
    const double d = m - s[i];
    sum_sq += d * d;
  }
  result.samples = n_total - k.index;
  result.mean_deviation = std::sqrt(sum_sq / static_cast<double>(result.samples));  // Eq. 5.1
  result.steady_mean = m;
  result.start_index = k.index;
  result.start_time_s = response.time_s(k.index);
  result.start_rule = k.rule;
  return result;
}

}  // namespace clearshape::metrics
