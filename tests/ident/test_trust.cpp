// The guard rails (ident/trust.hpp): a good fit of the thesis speed model is trusted; a parameter
// held at a bound, a search cut short, a poor fit, a pole at the Nyquist frequency are not;
// cross-validation prefers a trusted model among near-ties of the validation fit.
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/ident/cross_validation.hpp"
#include "clearshape/ident/trust.hpp"
#include "synthetic.hpp"

namespace ident = clearshape::ident;
namespace lti = clearshape::lti;
namespace t = clearshape::testing;

namespace {

bool mentions(const ident::TrustAssessment& a, const std::string& text) {
  return std::any_of(a.warnings.begin(), a.warnings.end(),
                     [&](const std::string& w) { return w.find(text) != std::string::npos; });
}

}  // namespace

TEST(Trust, GoodFitIsTrusted) {
  const auto truth = lti::thesis_speed_mode_model();
  const std::vector<ident::Experiment> data = {t::make_data(truth, t::step_input(2001), 1e-3, 0.01, 1, "step")};
  const auto e = ident::estimate_process_model(truth.structure(), data);
  const auto a = ident::assess(e);
  EXPECT_TRUE(a.trusted);
  EXPECT_TRUE(a.warnings.empty());
  for (const auto& p : e.parameters) EXPECT_FALSE(p.at_bound) << p.name;
}

TEST(Trust, ParameterOnItsBoundIsNotTrusted) {
  const auto truth = lti::thesis_speed_mode_model();  // ζ = 0.288
  const std::vector<ident::Experiment> data = {t::make_data(truth, t::step_input(2001), 1e-3, 0.01, 1, "step")};
  ident::ProcessFitOptions o;
  o.parameters["Zeta"].upper = 0.2;
  const auto e = ident::estimate_process_model(truth.structure(), data, o);
  EXPECT_TRUE(e.parameter("Zeta").at_bound);
  const auto a = ident::assess(e);
  EXPECT_FALSE(a.trusted);
  EXPECT_TRUE(mentions(a, "Zeta = 0.2 sits at a bound")) << (a.warnings.empty() ? "" : a.warnings[0]);
}

TEST(Trust, PoorFitAndUnconvergedSearchAreNotTrusted) {
  const auto truth = lti::thesis_speed_mode_model();
  // A first-order model cannot follow the oscillating step response and noise of 100 % hides it.
  const std::vector<ident::Experiment> noisy = {t::make_data(truth, t::step_input(2001), 1e-3, 1.0, 2, "noisy")};
  const auto poor = ident::estimate_process_model(lti::ProcessStructure::parse("P1"), noisy);
  ASSERT_LT(poor.fit_percent(), 80.0);
  EXPECT_TRUE(mentions(ident::assess(poor), "poor fit"));
  EXPECT_FALSE(ident::assess(poor).trusted);

  const std::vector<ident::Experiment> data = {t::make_data(truth, t::step_input(2001), 1e-3, 0.01, 1, "step")};
  ident::ProcessFitOptions o;
  o.max_iterations = 1;
  o.starts = 1;
  const auto cut = ident::estimate_process_model(truth.structure(), data, o);
  if (!cut.converged) {
    EXPECT_TRUE(mentions(ident::assess(cut), "did not converge"));
  }
  ident::ProcessEstimate forced = cut;
  forced.converged = false;
  EXPECT_FALSE(ident::assess(forced).trusted);
}

TEST(Trust, APoleAtTheNyquistFrequencyIsAliased) {
  const auto truth = lti::thesis_speed_mode_model();
  const std::vector<ident::Experiment> data = {t::make_data(truth, t::step_input(2001), 1e-3, 0.01, 1, "step")};
  const auto e = ident::estimate_process_model(truth.structure(), data);
  double fastest = 0.0;
  for (const auto& p : e.model.poles()) fastest = std::max(fastest, std::abs(p));
  ident::TrustOptions o;
  o.sample_time_s = 1e-3;  // the record's: every pole far below π/T
  EXPECT_TRUE(ident::assess(e, o).trusted);
  o.sample_time_s = 0.95 * 3.141592653589793 / fastest;  // as if sampled so that the fastest pole sits at 95 % of π/T
  const auto a = ident::assess(e, o);
  EXPECT_FALSE(a.trusted);
  EXPECT_TRUE(mentions(a, "of the Nyquist frequency")) << (a.warnings.empty() ? "" : a.warnings[0]);
}

TEST(Trust, CrossValidationPrefersATrustedModelAmongNearTies) {
  const auto truth = lti::thesis_speed_mode_model();
  const double dt = 1e-3;
  const std::vector<ident::Experiment> data = {
      t::make_data(truth, t::step_input(2001), dt, 0.01, 1, "step"),
      t::make_data(truth, t::sine_input(2001, dt, 1.0, 2.0), dt, 0.01, 3, "sine"),
      t::make_data(truth, t::prbs_input(2001, 20, 1.0, 4), dt, 0.01, 4, "prbs"),
  };
  const auto cv = ident::cross_validate(truth.structure(), data);
  ASSERT_EQ(cv.trust.size(), 3u);
  EXPECT_TRUE(cv.best_trusted);
  EXPECT_TRUE(cv.trust[cv.best].trusted);
  // With every model on a bound none is trusted: the best by score is kept and flagged.
  ident::CrossValidationOptions co;
  co.fit.parameters["Zeta"].upper = 0.2;  // every model now sits on the bound: none trusted
  const auto bounded = ident::cross_validate(truth.structure(), data, co);
  EXPECT_FALSE(bounded.best_trusted);
  EXPECT_FALSE(bounded.trust[bounded.best].trusted);
}
