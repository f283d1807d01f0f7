#pragma once
// Whether an identified model may be trusted: the guard rails of `identify`, `modes` and the
// study's cross-validation (a model that fails them is never selected as the best).
//
// A model is not trusted when the optimizer did not converge, a free parameter ended on a bound
// of the search, a free parameter's 1σ is not finite (not determined by the data), or its fit is
// poor (mean NRMSE fit below `min_fit_percent`).
#include <string>
#include <vector>

#include "clearshape/ident/process_fit.hpp"

namespace clearshape::ident {

struct TrustOptions {
  double min_fit_percent = 80.0;  ///< NRMSE fit % below which the fit is "poor"
};

struct TrustAssessment {
  bool trusted = true;
  std::vector<std::string> warnings;  ///< one sentence per failed check
};

TrustAssessment assess(const ProcessEstimate& estimate, const TrustOptions& options = {});

}  // namespace clearshape::ident
