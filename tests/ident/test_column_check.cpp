// ident::is_converted_copy: an output that is the input through a D/A (quantised, held until the
// next update) is recognised; a servo's lagging response to the same input is not.
#include <algorithm>
#include <cmath>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/ident/column_check.hpp"

namespace ident = clearshape::ident;

namespace {

// A 20° step ramped over 33 ms from 0.5 s, 1 kHz, 3 s.
std::vector<double> command() {
  std::vector<double> u(3000, 0.0);
  for (std::size_t k = 0; k < u.size(); ++k) u[k] = 20.0 * std::clamp((static_cast<double>(k) - 500.0) / 33.0, 0.0, 1.0);
  return u;
}

// The command as a 30 Hz pulse drive applies it: held between updates, quantised to 0.12°.
std::vector<double> applied(const std::vector<double>& u) {
  std::vector<double> y(u.size());
  for (std::size_t k = 0; k < u.size(); ++k) {
    const std::size_t update = (k / 33) * 33;
    y[k] = 0.12 * std::round(u[update] / 0.12);
  }
  return y;
}

}  // namespace

TEST(ColumnCheck, TheAppliedCommandIsACopyOfTheCommand) {
  const auto u = command();
  EXPECT_TRUE(ident::is_converted_copy(u, applied(u), 50));  // a 50 ms hold at 1 kHz
  EXPECT_TRUE(ident::is_converted_copy(u, u, 0));
  // The 30 Hz hold lasts 28 samples after the change: a shorter allowed hold rejects it.
  EXPECT_FALSE(ident::is_converted_copy(u, applied(u), 10));
}

TEST(ColumnCheck, AServoResponseIsNotACopy) {
  // A second-order response (15 Hz, ζ 0.3) of the motor to the command: it lags for longer than a hold.
  const auto u = command();
  std::vector<double> y(u.size(), 0.0);
  double x = 0.0, v = 0.0;
  const double w = 2.0 * 3.141592653589793 * 15.0, dt = 1e-3;
  for (std::size_t k = 0; k < u.size(); ++k) {
    y[k] = x;
    const double a = w * w * (u[k] - x) - 2.0 * 0.3 * w * v;
    v += a * dt;
    x += v * dt;
  }
  EXPECT_FALSE(ident::is_converted_copy(u, y, 50));
  // A constant pair proves nothing.
  EXPECT_FALSE(ident::is_converted_copy(std::vector<double>(10, 1.0), std::vector<double>(10, 1.0), 0));
  EXPECT_THROW((void)ident::is_converted_copy(std::vector<double>(3, 0.0), std::vector<double>(2, 0.0), 0), clearshape::InvalidArgument);
}
