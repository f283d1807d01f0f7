#include "clearshape/ident/residuals.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdlib>

#include <Eigen/Dense>
#include <unsupported/Eigen/FFT>
#include <fmt/format.h>

#include "clearshape/core/distributions.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"

namespace clearshape::ident {

namespace {

std::vector<double> centred(std::span<const double> x, const char* name) {
  double mean = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i])) throw InvalidArgument(fmt::format("residual tests: {} sample {} is not finite ({})", name, i, x[i]));
    mean += x[i];
  }
  mean /= static_cast<double>(x.size());
  std::vector<double> c(x.begin(), x.end());
  for (double& v : c) v -= mean;
  return c;
}

// Biased cross-covariance R_ab(τ) = (1/N) Σ_t a(t) b(t − τ), any sign of τ (Ljung §16.6).
double covariance(const std::vector<double>& a, const std::vector<double>& b, long lag) {
  const long n = static_cast<long>(a.size());
  double s = 0.0;
  for (long t = std::max(0L, lag); t < std::min(n, n + lag); ++t) {
    s += a[static_cast<std::size_t>(t)] * b[static_cast<std::size_t>(t - lag)];
  }
  return s / static_cast<double>(n);
}

// Normalised autocorrelation r(τ), τ = 0 … max_lag.
std::vector<double> autocorrelation(const std::vector<double>& x, std::size_t max_lag) {
  std::vector<double> r(max_lag + 1);
  const double r0 = covariance(x, x, 0);
  for (std::size_t k = 0; k <= max_lag; ++k) r[k] = covariance(x, x, static_cast<long>(k)) / r0;
  return r;
}

double chi2_survival(double statistic, std::size_t dof) {
  return distributions::chi_squared_upper_tail(static_cast<double>(dof), std::max(statistic, 0.0));
}

// The lag with the largest |r| among lags[from…], its count beyond the band.
void mark_worst(CorrelationTest& t, std::size_t from) {
  double worst_abs = -1.0;
  for (std::size_t i = from; i < t.lags.size(); ++i) {
    const double a = std::abs(t.correlation[i]);
    if (a > t.band) ++t.outside;
    if (a > worst_abs) {
      worst_abs = a;
      t.worst_lag = t.lags[i];
      t.worst = t.correlation[i];
    }
  }
}

CorrelationTest whiteness(const std::vector<double>& e, const ResidualTestOptions& o, double z) {
  const std::size_t m = o.max_lag;
  const double n = static_cast<double>(e.size());
  CorrelationTest t;
  t.correlation = autocorrelation(e, m);
  for (std::size_t k = 0; k <= m; ++k) t.lags.push_back(static_cast<int>(k));
  t.band = z / std::sqrt(n);
  mark_worst(t, 1);
  for (std::size_t k = 1; k <= m; ++k) t.statistic += t.correlation[k] * t.correlation[k] / (n - static_cast<double>(k));
  t.statistic *= n * (n + 2.0);  // Ljung & Box (1978)
  t.degrees_of_freedom = m - o.model_parameters;
  t.p_value = chi2_survival(t.statistic, t.degrees_of_freedom);
  t.passed = t.p_value >= 1.0 - o.confidence;
  return t;
}

// P(d) = Σ_k rₑ(k) rᵤ(k + d) over every lag, d = 0 … 2M (Ljung §16.6): through the FFT, as the
// inverse transform of the product of the two periodograms (zero-padded: linear, not circular).
// A product of periodograms is ≥ 0, so the Toeplitz matrix P is positive semi-definite.
std::vector<double> cross_covariance_kernel(const std::vector<double>& e, const std::vector<double>& u, std::size_t m) {
  const std::size_t n = e.size();
  std::size_t length = 1;
  while (length < 2 * n + 2 * m) length *= 2;
  std::vector<double> pe(length, 0.0), pu(length, 0.0);
  std::copy(e.begin(), e.end(), pe.begin());
  std::copy(u.begin(), u.end(), pu.begin());
  Eigen::FFT<double> fft;
  std::vector<std::complex<double>> fe, fu, product(length);
  fft.fwd(fe, pe);
  fft.fwd(fu, pu);
  for (std::size_t k = 0; k < length; ++k) product[k] = std::norm(fe[k]) * std::norm(fu[k]);
  std::vector<std::complex<double>> kernel;
  fft.inv(kernel, product);  // Eigen's inverse includes 1/length
  const double scale = static_cast<double>(n) * static_cast<double>(n) * covariance(e, e, 0) * covariance(u, u, 0);
  std::vector<double> p(2 * m + 1);
  for (std::size_t d = 0; d <= 2 * m; ++d) p[d] = kernel[d].real() / scale;
  return p;
}

// N·rᵀP⁻¹r over the eigenvalues of P above 1e-10 of the largest (Ljung §16.6); dof = their count.
void chi2_of_correlations(CorrelationTest& t, const std::vector<double>& kernel, double n) {
  const auto size = static_cast<Eigen::Index>(t.correlation.size());
  Eigen::MatrixXd p(size, size);
  for (Eigen::Index i = 0; i < size; ++i) {
    for (Eigen::Index j = 0; j < size; ++j) p(i, j) = kernel[static_cast<std::size_t>(std::labs(i - j))];
  }
  const Eigen::Map<const Eigen::VectorXd> r(t.correlation.data(), size);
  const linalg::SymmetricEigenDecomposition eig = linalg::symmetric_eigen(p);
  const double floor = 1e-10 * eig.values.maxCoeff();
  for (Eigen::Index i = 0; i < size; ++i) {
    const double lambda = eig.values(i);
    if (lambda <= floor) continue;
    const double proj = eig.vectors.col(i).dot(r);
    t.statistic += n * proj * proj / lambda;
    ++t.degrees_of_freedom;
  }
}

CorrelationTest independence(const std::vector<double>& u, const std::vector<double>& e, const ResidualTestOptions& o,
                             double z) {
  const std::size_t m = o.max_lag;
  const double n = static_cast<double>(e.size());
  const double scale = std::sqrt(covariance(e, e, 0) * covariance(u, u, 0));
  CorrelationTest t;
  for (long k = -static_cast<long>(m); k <= static_cast<long>(m); ++k) {
    t.lags.push_back(static_cast<int>(k));
    t.correlation.push_back(covariance(e, u, k) / scale);
  }
  const auto kernel = cross_covariance_kernel(e, u, m);
  t.band = z * std::sqrt(kernel[0] / n);
  mark_worst(t, 0);
  chi2_of_correlations(t, kernel, n);
  t.p_value = chi2_survival(t.statistic, t.degrees_of_freedom);
  t.passed = t.p_value >= 1.0 - o.confidence;
  return t;
}

void check_options(std::size_t samples, const ResidualTestOptions& o) {
  if (o.max_lag == 0) throw_invalid("max_lag", 0.0, ">= 1");
  if (samples <= 3 * o.max_lag + 1) {
    throw InvalidArgument(fmt::format("residual tests: max_lag = {} needs more than 3·max_lag + 1 = {} samples; the record has {}. "
                                      "Allowed: max_lag < (samples − 1)/3", o.max_lag, 3 * o.max_lag + 1, samples));
  }
  if (!(o.confidence > 0.0 && o.confidence < 1.0)) throw_invalid("confidence", o.confidence, "in (0, 1)");
  if (o.model_parameters >= o.max_lag) {
    throw_invalid("model_parameters", static_cast<double>(o.model_parameters), fmt::format("< max_lag = {}", o.max_lag));
  }
}

}  // namespace

double two_sided_z(double confidence) {
  if (!(confidence > 0.0 && confidence < 1.0)) throw_invalid("confidence", confidence, "in (0, 1)");
  return distributions::normal_quantile(0.5 + 0.5 * confidence);
}

ResidualTests residual_tests(std::span<const double> input, std::span<const double> residual,
                             const ResidualTestOptions& options) {
  if (input.size() != residual.size()) {
    throw InvalidArgument(fmt::format("residual tests: input has {} samples and residual {}; allowed: the same length",
                                      input.size(), residual.size()));
  }
  check_options(residual.size(), options);
  const auto e = centred(residual, "residual");
  const auto u = centred(input, "input");
  const double z = two_sided_z(options.confidence);
  ResidualTests out;
  out.samples = residual.size();
  out.confidence = options.confidence;
  if (covariance(e, e, 0) <= 0.0) {
    out.untested = "the residual is constant (an exact fit): nothing to test";
    return out;
  }
  out.whiteness = whiteness(e, options, z);
  if (covariance(u, u, 0) <= 0.0) {
    out.untested = "the input is constant: its independence from the residual cannot be tested";
    return out;
  }
  out.independence = independence(u, e, options, z);
  return out;
}

}  // namespace clearshape::ident
