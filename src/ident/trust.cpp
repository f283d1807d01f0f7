#include "clearshape/ident/trust.hpp"

#include <cmath>

#include <fmt/format.h>

#include "clearshape/core/units.hpp"

namespace clearshape::ident {

TrustAssessment assess(const ProcessEstimate& e, const TrustOptions& options) {
  TrustAssessment t;
  if (!e.converged) t.warnings.push_back("the optimizer did not converge");
  for (const auto& p : e.parameters) {
    if (p.fixed) continue;
    if (p.at_bound) t.warnings.push_back(fmt::format("{} = {:.6g} sits at a bound of the search", p.name, p.value));
    if (!std::isfinite(p.std_dev)) t.warnings.push_back(fmt::format("the 1σ of {} is not finite (the data do not determine it)", p.name));
  }
  const double fit = e.fit_percent();
  if (!(fit >= options.min_fit_percent)) {
    t.warnings.push_back(fmt::format("poor fit: {:.1f} % (below {:.0f} %)", fit, options.min_fit_percent));
  }
  if (options.sample_time_s > 0.0) {
    const double nyquist_rad_s = kPi / options.sample_time_s;  // ω_N = π / T
    for (const auto& p : e.model.poles()) {
      if (p.imag() >= 0.0 && std::abs(p) >= kAliasedFraction * nyquist_rad_s) {
        t.warnings.push_back(fmt::format("a pole at {:.4g} rad/s is at {:.0f} % of the Nyquist frequency ({:.4g} rad/s): aliased, the record "
                                         "cannot resolve it (try a model with fewer poles)",
                                         std::abs(p), 100.0 * std::abs(p) / nyquist_rad_s, nyquist_rad_s));
      }
    }
  }
  t.trusted = t.warnings.empty();
  return t;
}

}  // namespace clearshape::ident
