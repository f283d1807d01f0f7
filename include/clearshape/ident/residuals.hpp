#pragma once
// Residual analysis of an identified model, as MATLAB's `resid` (Ljung, System Identification,
// 2nd ed., §16.6): is the residual e = y − ŷ white, and is it independent of past and future inputs?
//
//   whiteness:    rₑ(τ) = Rₑ(τ)/Rₑ(0), τ = 0 … M, band ±z/√N (z = 2.576 at 99 %), and the
//                 Ljung–Box portmanteau Q = N(N+2) Σ_{τ=1}^{M} rₑ(τ)²/(N − τ) ~ χ²(M − p)
//                 (Ljung & Box 1978, Biometrika 65:297–303)
//   independence: rₑᵤ(τ) = Rₑᵤ(τ)/√(Rₑ(0)Rᵤ(0)), τ = −M … M, where Rₑᵤ(τ) = (1/N) Σ e(t)u(t−τ);
//                 under independence √N·rₑᵤ is normal with covariance P(τ₁−τ₂) = Σₖ rₑ(k) rᵤ(k+τ₁−τ₂)
//                 (Ljung §16.6): the band is ±z√(P(0)/N) — wider when both are coloured — and
//                 N·rₑᵤᵀP⁻¹rₑᵤ ~ χ²(2M+1) (Ljung §16.6) decides.
//
// Correlations are of the mean-removed signals, biased (divided by N). The sum for P runs over
// every lag (a sum truncated at |k| ≤ M overstates P for coloured signals: the test then almost
// never rejects); computed as the product of the two periodograms, it is positive semi-definite.
// An output-error model (what `identify` fits) does not model the noise, so its residual need not
// be white; independence from the input is the test that says the dynamics are complete.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace clearshape::ident {

struct ResidualTestOptions {
  std::size_t max_lag = 25;          ///< M (MATLAB resid's default)
  double confidence = 0.99;          ///< of the band and the tests (MATLAB resid's default)
  std::size_t model_parameters = 0;  ///< p subtracted from the Ljung–Box degrees of freedom (ARMA residuals)
};

/// One correlation test: the normalised correlation at each lag, its band and the χ² test.
struct CorrelationTest {
  std::vector<int> lags;
  std::vector<double> correlation;  ///< normalised, at lags[i]
  double band = 0.0;                ///< ± this at every lag (confidence level of the options)
  std::size_t outside = 0;          ///< tested lags with |correlation| > band (lag 0 of whiteness not tested)
  int worst_lag = 0;                ///< tested lag of the largest |correlation| / band
  double worst = 0.0;               ///< that correlation
  double statistic = 0.0;           ///< Ljung–Box Q, or N·rᵀP⁻¹r
  std::size_t degrees_of_freedom = 0;
  double p_value = 1.0;             ///< P(χ² > statistic)
  bool passed = true;               ///< p_value ≥ 1 − confidence
};

struct ResidualTests {
  std::optional<CorrelationTest> whiteness;     ///< lags 0 … M; none when the residual is constant
  std::optional<CorrelationTest> independence;  ///< lags −M … M (positive τ: e(t) with the earlier u(t − τ));
                                                ///< none when the input or the residual is constant
  std::string untested;                         ///< why a test is missing ("" when both ran)
  std::size_t samples = 0;
  double confidence = 0.99;
};

/// Both tests on one experiment. Throws InvalidArgument (naming the option and its range) when
/// the sizes differ, a sample is not finite, max_lag is 0 or the record is not longer than
/// 3·max_lag + 1 samples, confidence is outside (0, 1) or model_parameters ≥ max_lag. A constant
/// residual (an exact fit) leaves both tests out, a constant input the independence test; `untested` says why.
ResidualTests residual_tests(std::span<const double> input, std::span<const double> residual,
                             const ResidualTestOptions& options = {});

/// Normal quantile z with P(|Z| ≤ z) = confidence (2.5758 at 0.99).
double two_sided_z(double confidence);

}  // namespace clearshape::ident
