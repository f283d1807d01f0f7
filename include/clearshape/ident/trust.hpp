#pragma once
// Whether an identified model may be trusted: the guard rails of `identify`, `modes` and the
// cross-validation (where trust breaks near-ties of the validation fit, cross_validation.hpp).
//
// A model is not trusted when the optimizer did not converge, a free parameter ended on a bound
// of the search, a free parameter's 1σ is not finite (not determined by the data), its fit is
// poor (mean NRMSE fit below `min_fit_percent`), or — given the sample time — a pole lies at or
// beyond 90 % of the Nyquist frequency (aliased: the record cannot resolve it).
#include <string>
#include <vector>

#include "clearshape/ident/process_fit.hpp"

namespace clearshape::ident {

struct TrustOptions {
  double min_fit_percent = 80.0;  ///< NRMSE fit % below which the fit is "poor"
  double sample_time_s = 0.0;     ///< > 0: flag poles with |s| ≥ kAliasedFraction · π / sample_time_s
};

struct TrustAssessment {
  bool trusted = true;
  std::vector<std::string> warnings;  ///< one sentence per failed check
};

/// A pole this close to the Nyquist frequency (as a fraction of π/T) is aliased.
inline constexpr double kAliasedFraction = 0.9;

TrustAssessment assess(const ProcessEstimate& estimate, const TrustOptions& options = {});

}  // namespace clearshape::ident
