// core/distributions.hpp against published tables and closed forms: the χ² quantiles of the
// NIST/SEMATECH e-Handbook of Statistical Methods, Table 1.3.6.7.4 (upper-tail 0.01 and 0.05
// critical values), the normal quantile of its Table 1.3.6.7.1, and the χ² upper tail with two
// degrees of freedom, which is exp(−x/2) exactly.
#include <gtest/gtest.h>

#include <cmath>

#include "clearshape/core/distributions.hpp"

namespace clearshape::distributions {
namespace {

TEST(Distributions, ChiSquaredQuantilesAreTheNistTables) {
  EXPECT_NEAR(chi_squared_quantile(1.0, 0.99), 6.635, 5e-4);
  EXPECT_NEAR(chi_squared_quantile(3.0, 0.99), 11.345, 5e-4);
  EXPECT_NEAR(chi_squared_quantile(10.0, 0.99), 23.209, 5e-4);
  EXPECT_NEAR(chi_squared_quantile(25.0, 0.95), 37.652, 5e-4);
  EXPECT_NEAR(chi_squared_quantile(9.0, 0.05), 3.325, 5e-4);  // the lower tail: 0.95 upper
}

TEST(Distributions, TheUpperTailWithTwoDegreesIsExponential) {
  for (const double x : {0.0, 0.5, 3.0, 40.0, 200.0}) {
    EXPECT_NEAR(chi_squared_upper_tail(2.0, x) / std::exp(-0.5 * x), 1.0, 1e-13) << x;  // no 1 − cdf underflow
  }
  EXPECT_NEAR(chi_squared_upper_tail(3.0, chi_squared_quantile(3.0, 0.99)), 0.01, 1e-12);
}

TEST(Distributions, NormalQuantileIsTheTable) {
  EXPECT_NEAR(normal_quantile(0.975), 1.960, 5e-4);
  EXPECT_NEAR(normal_quantile(0.995), 2.576, 5e-4);
  EXPECT_DOUBLE_EQ(normal_quantile(0.5), 0.0);
  EXPECT_NEAR(normal_quantile(0.025), -normal_quantile(0.975), 1e-15);
}

}  // namespace
}  // namespace clearshape::distributions
