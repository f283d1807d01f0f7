#include "clearshape/metrics/improvement.hpp"

#include "clearshape/core/error.hpp"
#include "validate.hpp"

namespace clearshape::metrics {

double improvement_percent(double without, double with) {
  require_positive("without (figure of merit without shaping)", without,
                   "The improvement is relative to it");
  require_non_negative("with (figure of merit with shaping)", with);
  return (without - with) / without * 100.0;  // thesis §5.1.2, Appendix B
}

double mean_of(std::span<const double> values) {
  detail::require_min_size("values", values.size(), 1);
  detail::require_finite_samples("values", values);
  double sum = 0.0;
  for (const double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

}  // namespace clearshape::metrics
