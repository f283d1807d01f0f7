// Residual tests (MATLAB resid; Ljung, System Identification, 2nd ed., §16.6) against the NumPy/SciPy
// code of tests/golden/gen_resid.py (correlations and bands 1e-12, statistics 1e-9 relative,
// p-values 1e-9 relative or 1e-300 absolute), and their false-alarm rate on seeded records.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <random>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/residuals.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
namespace ident = clearshape::ident;
using nlohmann::json;

namespace {

json golden() {
  std::ifstream in(clearshape::testing::golden_path("ident_resid.json"));
  return json::parse(in);
}

void expect_matches(const ident::CorrelationTest& t, const json& ref, const std::string& what) {
  const auto r = ref["correlation"].get<std::vector<double>>();
  ASSERT_EQ(t.correlation.size(), r.size()) << what;
  for (std::size_t i = 0; i < r.size(); ++i) EXPECT_NEAR(t.correlation[i], r[i], 1e-12) << what << " lag " << t.lags[i];
  EXPECT_NEAR(t.band, ref["band"].get<double>(), 1e-12) << what;
  EXPECT_NEAR(t.statistic, ref["statistic"].get<double>(), 1e-9 * ref["statistic"].get<double>()) << what;
  EXPECT_EQ(t.degrees_of_freedom, ref["dof"].get<std::size_t>()) << what;
  const double p = ref["p_value"].get<double>();
  EXPECT_NEAR(t.p_value, p, std::max(1e-9 * p, 1e-300)) << what;
}

// A low-passed (coloured) input: a first-order recursion on seeded white noise.
std::vector<double> coloured(std::mt19937_64& rng, std::size_t n, double pole) {
  std::normal_distribution<double> white(0.0, 1.0);
  std::vector<double> x(n);
  double s = 0.0;
  for (double& v : x) v = s = pole * s + white(rng);
  return x;
}

}  // namespace

TEST(Residuals, MatchNumpyAndScipy) {
  const json g = golden();
  const auto u = g["input"].get<std::vector<double>>();
  ident::ResidualTestOptions o;
  o.max_lag = g["max_lag"].get<std::size_t>();
  EXPECT_NEAR(ident::two_sided_z(0.99), g["z"].get<double>(), 1e-12);
  for (const auto& c : g["cases"]) {
    const auto e = c["residual"].get<std::vector<double>>();
    const auto r = ident::residual_tests(u, e, o);
    const std::string name = c["name"].get<std::string>();
    ASSERT_TRUE(r.whiteness && r.independence) << r.untested;
    expect_matches(*r.whiteness, c["whiteness"], name + " whiteness");
    expect_matches(*r.independence, c["independence"], name + " independence");
    std::printf("[ ident ] resid %s: Q %.6g (numpy %.6g) p %.3g, independence chi2 %.6g (numpy %.6g) p %.3g\n",
                name.c_str(), r.whiteness->statistic, c["whiteness"]["statistic"].get<double>(), r.whiteness->p_value,
                r.independence->statistic, c["independence"]["statistic"].get<double>(), r.independence->p_value);
  }
  // The verdicts the generator's construction implies.
  const auto& cases = g["cases"];
  EXPECT_TRUE(ident::residual_tests(u, cases[0]["residual"].get<std::vector<double>>(), o).whiteness->passed);
  EXPECT_TRUE(ident::residual_tests(u, cases[0]["residual"].get<std::vector<double>>(), o).independence->passed);
  EXPECT_FALSE(ident::residual_tests(u, cases[1]["residual"].get<std::vector<double>>(), o).whiteness->passed);
  EXPECT_TRUE(ident::residual_tests(u, cases[1]["residual"].get<std::vector<double>>(), o).independence->passed);
  EXPECT_FALSE(ident::residual_tests(u, cases[2]["residual"].get<std::vector<double>>(), o).independence->passed);
  o.model_parameters = 2;
  expect_matches(ident::residual_tests(u, cases[1]["residual"].get<std::vector<double>>(), o).whiteness.value(),
                 g["ar1_model_parameters_2"], "ar1 p=2");
}

TEST(Residuals, FalseAlarmRateIsTheNominalOne) {
  // Independent coloured input and coloured residual (the case where ±z/√N is too narrow): the
  // statistic's mean is its χ² degrees of freedom (2M + 1 = 51; 400 draws: ±3 is > 4 standard
  // errors), the test at 99 % rejects at most the nominal 1 % of 400 records (binomial 99.9 %
  // bound: ≤ 10), and the plain band ±z/√N on the same records is crossed far more often.
  std::mt19937_64 rng(20261126);
  ident::ResidualTestOptions o;
  int rejected = 0, naive_crossed = 0;
  double mean_statistic = 0.0;
  const int trials = 400;
  for (int i = 0; i < trials; ++i) {
    const auto u = coloured(rng, 1000, 0.9);
    const auto e = coloured(rng, 1000, 0.9);
    const auto r = ident::residual_tests(u, e, o);
    rejected += r.independence->passed ? 0 : 1;
    mean_statistic += r.independence->statistic / trials;
    const double naive = ident::two_sided_z(0.99) / std::sqrt(1000.0);
    naive_crossed += std::abs(r.independence->worst) > naive ? 1 : 0;
    EXPECT_GT(r.independence->band, naive);
  }
  std::printf("[ ident ] resid: independence mean chi2 %.2f (dof 51), rejected %d of %d (nominal 1 %%); the plain band "
              "crossed on %d\n", mean_statistic, rejected, trials, naive_crossed);
  EXPECT_NEAR(mean_statistic, 51.0, 3.0);
  EXPECT_LE(rejected, 10);
  EXPECT_GT(naive_crossed, 100);
  // White residuals: Ljung–Box at 99 % rejects ≈ 1 %.
  int not_white = 0;
  double mean_q = 0.0;
  std::normal_distribution<double> white(0.0, 1.0);
  for (int i = 0; i < trials; ++i) {
    const auto u = coloured(rng, 1000, 0.9);
    std::vector<double> e(1000);
    for (double& v : e) v = white(rng);
    const auto w = ident::residual_tests(u, e, o).whiteness.value();
    not_white += w.passed ? 0 : 1;
    mean_q += w.statistic / trials;
  }
  std::printf("[ ident ] resid: whiteness mean Q %.2f (dof 25), rejected %d of %d white records (nominal 1 %%)\n", mean_q,
              not_white, trials);
  EXPECT_NEAR(mean_q, 25.0, 1.5);
  EXPECT_LE(not_white, 10);
}

TEST(Residuals, RejectBadOptions) {
  std::mt19937_64 rng(3);
  const auto u = coloured(rng, 100, 0.5);
  const auto e = coloured(rng, 100, 0.0);
  ident::ResidualTestOptions o;
  try {
    ident::residual_tests(u, e, o);  // 100 ≤ 3·25 + 1 is false: passes
  } catch (const cs::InvalidArgument& ex) {
    ADD_FAILURE() << ex.what();
  }
  o.max_lag = 33;
  try {
    ident::residual_tests(u, e, o);
    ADD_FAILURE() << "max_lag 33 on 100 samples was accepted";
  } catch (const cs::InvalidArgument& ex) {
    EXPECT_NE(std::string(ex.what()).find("max_lag = 33"), std::string::npos) << ex.what();
  }
  o.max_lag = 0;
  EXPECT_THROW(ident::residual_tests(u, e, o), cs::InvalidArgument);
  o.max_lag = 10;
  o.confidence = 1.0;
  EXPECT_THROW(ident::residual_tests(u, e, o), cs::InvalidArgument);
  o.confidence = 0.95;
  o.model_parameters = 10;
  EXPECT_THROW(ident::residual_tests(u, e, o), cs::InvalidArgument);
  o.model_parameters = 0;
  const auto exact = ident::residual_tests(u, std::vector<double>(100, 1.0), o);  // constant residual: an exact fit
  EXPECT_FALSE(exact.whiteness.has_value());
  EXPECT_FALSE(exact.independence.has_value());
  EXPECT_NE(exact.untested.find("constant"), std::string::npos);
  const auto still = ident::residual_tests(std::vector<double>(100, 2.0), e, o);  // constant input: whiteness only
  EXPECT_TRUE(still.whiteness.has_value());
  EXPECT_FALSE(still.independence.has_value());
  EXPECT_THROW(ident::residual_tests(std::vector<double>(99, 1.0), e, o), cs::InvalidArgument);   // sizes differ
}
