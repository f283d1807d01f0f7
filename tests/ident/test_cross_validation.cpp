// Thesis §4.2 cross-validation on synthetic step, ramp, sine and PRBS records of the speed-mode
// model (Eq. 4.2): every model validates on every other input, the matrix has the estimation fits
// on its diagonal, and a record from a different plant is never chosen as the best.
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/cross_validation.hpp"
#include "synthetic.hpp"

namespace ident = clearshape::ident;
namespace lti = clearshape::lti;
namespace t = clearshape::testing;

TEST(CrossValidation, ThesisInputsOfTheSpeedModel) {
  const auto truth = lti::thesis_speed_mode_model();
  const double dt = 1e-3;
  std::vector<ident::Experiment> data = {
      t::make_data(truth, t::step_input(2001), dt, 0.01, 1, "step"),
      t::make_data(truth, t::ramp_input(2001, dt, 1.0), dt, 0.01, 2, "ramp"),
      t::make_data(truth, t::sine_input(2001, dt, 1.0, 2.0), dt, 0.01, 3, "sine"),
      t::make_data(truth, t::prbs_input(2001, 20, 1.0, 4), dt, 0.01, 4, "prbs"),
  };
  // A fifth record from another plant (slower, better damped).
  lti::ProcessParameters other = truth.parameters();
  other.tw = 0.09;
  other.zeta = 0.6;
  data.push_back(t::make_data(lti::ProcessModel("P3UZ", other), t::step_input(2001), dt, 0.01, 5, "other"));

  const auto cv = ident::cross_validate(truth.structure(), data);
  ASSERT_EQ(cv.fit_percent.rows(), 5);
  for (Eigen::Index i = 0; i < 5; ++i) {
    EXPECT_DOUBLE_EQ(cv.fit_percent(i, i), cv.estimates[static_cast<std::size_t>(i)].experiments[0].fit_percent);
  }
  for (Eigen::Index i = 0; i < 4; ++i)
    for (Eigen::Index j = 0; j < 4; ++j) EXPECT_GT(cv.fit_percent(i, j), 90.0) << i << " on " << j;
  for (Eigen::Index j = 0; j < 4; ++j) EXPECT_LT(cv.fit_percent(4, j), cv.fit_percent(0, j)) << "other on " << j;
  EXPECT_LT(cv.best, 4u);
  EXPECT_EQ(cv.names[cv.best], cv.names[cv.best]);
  ASSERT_TRUE(cv.joint.has_value());
  EXPECT_EQ(cv.joint_fit_percent.size(), 5u);
  // The best model's ωn, ζ are those of the truth.
  EXPECT_NEAR(*cv.estimates[cv.best].natural_frequency_rad_s(), 1.0 / 0.0479, 0.01 / 0.0479);
  EXPECT_NEAR(*cv.estimates[cv.best].damping_ratio(), 0.288, 0.01);
}

TEST(CrossValidation, NeedsTwoExperiments) {
  const auto truth = lti::thesis_speed_mode_model();
  std::vector<ident::Experiment> one = {t::make_data(truth, t::step_input(500), 1e-3, 0.0, 1)};
  EXPECT_THROW(ident::cross_validate(truth.structure(), one), clearshape::InvalidArgument);
}

TEST(CrossValidation, ValidationFitRanksFirstAndTrustBreaksNearTies) {
  const double nan = std::nan("");
  // The issue-20 case: a trusted model at −121 % never beats one at 92.8 % whose σ is not finite.
  EXPECT_EQ(ident::pick_best({-121.0, 92.8}, {true, false}, 1.0), 1u);
  // Within a point of the best, the trusted model wins.
  EXPECT_EQ(ident::pick_best({92.0, 92.8}, {true, false}, 1.0), 0u);
  EXPECT_EQ(ident::pick_best({92.0, 92.8}, {true, true}, 1.0), 1u);
  // A non-finite validation fit never wins; none finite: no best.
  EXPECT_EQ(ident::pick_best({nan, 50.0}, {true, false}, 1.0), 1u);
  EXPECT_EQ(ident::pick_best({INFINITY, 50.0}, {true, true}, 1.0), 1u);
  EXPECT_FALSE(ident::pick_best({nan, nan}, {true, true}, 1.0).has_value());
}
