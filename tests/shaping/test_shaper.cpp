// shaping/shaper.hpp helpers.
#include <gtest/gtest.h>

#include <vector>

#include "clearshape/core/error.hpp"
#include "clearshape/shaping/shaper.hpp"

// A search's amplitudes on a slot grid as a positive shaper (shaping::positive_shaper_on_slots).
TEST(PositiveShaperOnSlots, NormalisesDropsZerosAndFallsBackToAUnitImpulse) {
  const std::vector<double> slots{0.0, 0.1, 0.2, 0.3};
  const std::vector<double> x{0.5, -0.2, 0.0, 1.5};
  const auto s = clearshape::shaping::positive_shaper_on_slots("search", slots, x);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s.impulses()[0].time_s, 0.0);
  EXPECT_DOUBLE_EQ(s.impulses()[0].amplitude, 0.25);
  EXPECT_EQ(s.impulses()[1].time_s, 0.3);
  EXPECT_DOUBLE_EQ(s.impulses()[1].amplitude, 0.75);
  EXPECT_TRUE(s.is_positive());
  const std::vector<double> none{0.0, -1.0, 0.0, 0.0};
  const auto unit = clearshape::shaping::positive_shaper_on_slots("search", slots, none);
  ASSERT_EQ(unit.size(), 1u);
  EXPECT_EQ(unit.impulses()[0].time_s, 0.0);
  EXPECT_EQ(unit.impulses()[0].amplitude, 1.0);
  EXPECT_THROW(clearshape::shaping::positive_shaper_on_slots("search", slots, std::vector<double>{1.0}),
               clearshape::InvalidArgument);
}
