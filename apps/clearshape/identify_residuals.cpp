#include "identify_residuals.hpp"

#include <cmath>
#include <optional>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::cli {

namespace {

// A residual below this fraction of the output's RMS deviation (a fit above 99.9999 %) is rounding
// and simulation error of a noise-free record, not a disturbance: its correlations say nothing.
constexpr double kRoundingResidual = 1e-6;

double rms_deviation(const std::vector<double>& x) {
  double mean = 0.0, s = 0.0;
  for (double v : x) mean += v / static_cast<double>(x.size());
  for (double v : x) s += (v - mean) * (v - mean);
  return std::sqrt(s / static_cast<double>(x.size()));
}

void check_options(std::size_t max_lag, double confidence, std::size_t shortest) {
  if (max_lag < 1 || shortest <= 3 * max_lag + 1) {
    throw InvalidArgument(fmt::format("--resid-lags = {} is out of range; allowed: 1 … {} (fewer than a third of the "
                                      "shortest run's {} samples)", max_lag, shortest > 2 ? (shortest - 2) / 3 : 0, shortest));
  }
  if (!(confidence > 0.0 && confidence < 1.0)) {
    throw InvalidArgument(fmt::format("--resid-confidence = {} is out of range; allowed: (0, 1), e.g. 0.99", confidence));
  }
}

nlohmann::ordered_json test_json(const std::optional<ident::CorrelationTest>& test, const char* verdict_key) {
  if (!test) return nullptr;
  const ident::CorrelationTest& t = *test;
  return {{"lags", t.lags},          {"correlation", t.correlation}, {"band", t.band},
          {"lags_outside", t.outside}, {"worst_lag", t.worst_lag},    {"worst", t.worst},
          {"statistic", t.statistic}, {"degrees_of_freedom", t.degrees_of_freedom},
          {"p_value", t.p_value},     {verdict_key, t.passed}};
}

std::string test_line(const std::optional<ident::CorrelationTest>& test, const char* symbol, const char* statistic,
                      const char* pass, const char* fail) {
  if (!test) return "not tested";
  const ident::CorrelationTest& t = *test;
  const std::size_t tested = t.lags.front() == 0 ? t.lags.size() - 1 : t.lags.size();  // whiteness: lag 0 is 1 by definition
  return fmt::format("max |{}| {:.3g} at lag {} (band ±{:.3g}, {} of {} lags outside), {} {:.4g} ({} dof), p {:.3g}: {}",
                     symbol, std::abs(t.worst), t.worst_lag, t.band, t.outside, tested, statistic, t.statistic,
                     t.degrees_of_freedom, t.p_value, t.passed ? pass : fail);
}

}  // namespace

std::vector<ExperimentResiduals> test_residuals(const std::vector<ident::Experiment>& experiments,
                                                const ident::ProcessEstimate& estimate, std::size_t max_lag,
                                                double confidence) {
  std::size_t shortest = experiments.empty() ? 0 : experiments[0].output.size();
  for (const auto& e : experiments) shortest = std::min(shortest, e.output.size());
  check_options(max_lag, confidence, shortest);
  ident::ResidualTestOptions o;
  o.max_lag = max_lag;
  o.confidence = confidence;
  std::vector<ExperimentResiduals> out;
  for (std::size_t i = 0; i < experiments.size() && i < estimate.experiments.size(); ++i) {
    const auto& y = experiments[i].output;
    const auto& y_hat = estimate.experiments[i].simulated.values;
    std::vector<double> residual(y.size());
    for (std::size_t k = 0; k < y.size() && k < y_hat.size(); ++k) residual[k] = y[k] - y_hat[k];  // e = y − ŷ
    const double ratio = rms_deviation(residual) / rms_deviation(y);
    if (ratio < kRoundingResidual) {
      ident::ResidualTests none;
      none.samples = y.size();
      none.confidence = confidence;
      none.untested = fmt::format("the residual is {:.2g} of the output's RMS, rounding level (a noise-free record): nothing to test",
                                  ratio);
      out.push_back({experiments[i].name, std::move(none)});
      continue;
    }
    out.push_back({experiments[i].name, ident::residual_tests(experiments[i].input, residual, o)});
  }
  return out;
}

std::vector<std::string> residual_warnings(const std::vector<ExperimentResiduals>& residuals) {
  std::vector<std::string> w;
  for (const auto& r : residuals) {
    if (const auto& ind = r.tests.independence; ind && !ind->passed) {
      w.push_back(fmt::format("residual of '{}' depends on the input (chi2 {:.4g}, {} dof, p {:.3g}; largest at lag {}): the "
                              "model misses dynamics or a delay — try another structure or more poles",
                              r.name, ind->statistic, ind->degrees_of_freedom, ind->p_value, ind->worst_lag));
    }
    if (const auto& wh = r.tests.whiteness; wh && !wh->passed) {
      w.push_back(fmt::format("residual of '{}' is not white (Ljung-Box Q {:.4g}, p {:.3g}): expected of an output-error fit "
                              "with coloured noise; alone it does not reject the model", r.name, wh->statistic, wh->p_value));
    }
  }
  return w;
}

nlohmann::ordered_json residuals_json(const std::vector<ExperimentResiduals>& residuals, std::size_t max_lag) {
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const auto& r : residuals) {
    runs.push_back({{"name", r.name},
                    {"samples", r.tests.samples},
                    {"whiteness", test_json(r.tests.whiteness, "white")},
                    {"independence", test_json(r.tests.independence, "independent")},
                    {"untested", r.tests.untested}});
  }
  nlohmann::ordered_json j;
  j["method"] = "MATLAB resid; Ljung, System Identification, 2nd ed., 16.6; Ljung-Box Q for whiteness";
  j["max_lag"] = max_lag;
  j["confidence"] = residuals.empty() ? 0.0 : residuals[0].tests.confidence;
  j["experiments"] = runs;
  return j;
}

void print_residuals(const std::vector<ExperimentResiduals>& residuals, std::size_t max_lag) {
  if (residuals.empty()) return;
  fmt::print("\n  residual tests (MATLAB resid, Ljung §16.6): lags up to {}, {:g} % confidence\n", max_lag,
             100.0 * residuals[0].tests.confidence);
  for (const auto& r : residuals) {
    const auto& t = r.tests;
    fmt::print("  {:<20} whiteness    {}\n", r.name, test_line(t.whiteness, "r_e", "Ljung-Box Q", "white", "NOT white"));
    fmt::print("  {:<20} independence {}\n", "",
               test_line(t.independence, "r_eu", "chi2", "independent", "NOT independent"));
    if (!t.untested.empty()) fmt::print("  {:<20} ({})\n", "", t.untested);
  }
}

}  // namespace clearshape::cli
