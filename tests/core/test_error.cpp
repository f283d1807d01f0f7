#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "clearshape/core/error.hpp"
#include "clearshape/core/series.hpp"
#include "clearshape/core/units.hpp"

namespace cs = clearshape;

TEST(Error, InvalidMessageNamesParameterValueRangeAndRemedy) {
  try {
    cs::require_in_half_open("zeta", 1.2, 0.0, 1.0, "Identify the mode first");
    FAIL() << "expected InvalidArgument";
  } catch (const cs::InvalidArgument& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("zeta = 1.2"), std::string::npos) << m;
    EXPECT_NE(m.find("[0, 1)"), std::string::npos) << m;
    EXPECT_NE(m.find("Identify the mode first"), std::string::npos) << m;
  }
}

TEST(Error, RangeChecksRejectNonFiniteAndBoundaries) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(cs::require_finite("x", nan), cs::InvalidArgument);
  EXPECT_THROW(cs::require_positive("x", 0.0), cs::InvalidArgument);
  EXPECT_NO_THROW(cs::require_positive("x", 1e-300));
  EXPECT_THROW(cs::require_non_negative("x", -1e-300), cs::InvalidArgument);
  EXPECT_NO_THROW(cs::require_in_closed("x", 1.0, 0.0, 1.0));
  EXPECT_THROW(cs::require_in_open("x", 1.0, 0.0, 1.0), cs::InvalidArgument);
  EXPECT_THROW(cs::require_in_closed("x", nan, 0.0, 1.0), cs::InvalidArgument);
}

TEST(Error, InputErrorCarriesFileLineField) {
  const cs::InputError e("run.csv", 12, "time_s", "not a number");
  EXPECT_EQ(std::string(e.what()), "run.csv:12: field 'time_s': not a number");
  EXPECT_EQ(e.line(), 12u);
  EXPECT_EQ(e.field(), "time_s");
}

TEST(Units, ConversionsRoundTrip) {
  EXPECT_DOUBLE_EQ(cs::deg_to_rad(180.0), cs::kPi);
  EXPECT_DOUBLE_EQ(cs::rad_to_deg(cs::deg_to_rad(37.5)), 37.5);
  EXPECT_DOUBLE_EQ(cs::hz_to_rad_s(1.0), 2.0 * cs::kPi);
}

TEST(Series, SampleCountIncludesBothEnds) {
  EXPECT_EQ(cs::sample_count(5.0, 1e-3), 5001u);
  EXPECT_EQ(cs::sample_count(0.0, 1e-3), 1u);
  EXPECT_EQ(cs::sample_count(0.3, 0.1), 4u);  // 0.3/0.1 = 2.9999999999999996
  EXPECT_THROW(cs::sample_count(1.0, 0.0), cs::InvalidArgument);
}
