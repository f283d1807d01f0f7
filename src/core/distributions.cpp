#include "clearshape/core/distributions.hpp"

#include <boost/math/distributions/chi_squared.hpp>
#include <boost/math/distributions/normal.hpp>

namespace clearshape::distributions {

double chi_squared_quantile(double dof, double p) { return boost::math::quantile(boost::math::chi_squared(dof), p); }

double chi_squared_upper_tail(double dof, double x) {
  return boost::math::cdf(boost::math::complement(boost::math::chi_squared(dof), x));
}

double normal_quantile(double p) { return boost::math::quantile(boost::math::normal(), p); }

}  // namespace clearshape::distributions
