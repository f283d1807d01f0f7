#include "clearshape/metrics/mean_deviation.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <span>
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

// First index i >= from where the response meets M: s_i == M, or s_i − M changes sign
// with respect to s_{i−1} − M (the thesis's "first coincide point", §5.1.2).
std::optional<std::size_t> first_coincidence(std::span<const double> s, std::size_t from,
                                             double m) {
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

}  // namespace

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
  std::vector<std::size_t> visited;
  std::size_t k = first_coincidence(s, from, m).value_or(window_start);
  visited.push_back(k);
  for (int it = 1; it <= options.max_iterations; ++it) {
    result.iterations = it;
    m = mean_from(s, k);  // M = mean of the steady-state part
    const std::size_t next = first_coincidence(s, from, m).value_or(k);
    if (next == k) {
      result.converged = true;
      break;
    }
    if (std::find(visited.begin(), visited.end(), next) != visited.end()) {
      k = next;
      m = mean_from(s, k);
      break;  // a cycle: converged stays false
    }
    k = next;
    visited.push_back(k);
    if (it == options.max_iterations) m = mean_from(s, k);
  }

  double sum_sq = 0.0;
  for (std::size_t i = k; i < n_total; ++i) {
    const double d = m - s[i];
    sum_sq += d * d;
  }
  result.samples = n_total - k;
  result.mean_deviation = std::sqrt(sum_sq / static_cast<double>(result.samples));  // Eq. 5.1
  result.steady_mean = m;
  result.start_index = k;
  result.start_time_s = response.time_s(k);
  return result;
}

}  // namespace clearshape::metrics
