#include "covariance.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "clearshape/core/distributions.hpp"
#include "clearshape/core/linalg.hpp"

namespace clearshape::ident::detail {

namespace {

// The residuals and Jacobian at the current parameters, and where each residual block (an
// experiment) starts: lags never cross from one record into the next.
struct Evaluated {
  Eigen::VectorXd residuals;
  Eigen::MatrixXd jacobian;
  std::vector<Eigen::Index> segment_starts;
  bool ok = false;
};

Evaluated evaluate(ceres::Problem& problem, const std::vector<double*>& blocks) {
  Evaluated out;
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = blocks;
  eo.num_threads = 1;
  problem.GetResidualBlocks(&eo.residual_blocks);
  ceres::CRSMatrix crs;
  double cost = 0.0;
  std::vector<double> r;
  if (!problem.Evaluate(eo, &cost, &r, nullptr, &crs)) return out;
  out.residuals = Eigen::Map<const Eigen::VectorXd>(r.data(), static_cast<Eigen::Index>(r.size()));
  out.jacobian = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int row = 0; row < crs.num_rows; ++row)
    for (int k = crs.rows[static_cast<std::size_t>(row)]; k < crs.rows[static_cast<std::size_t>(row) + 1]; ++k)
      out.jacobian(row, crs.cols[static_cast<std::size_t>(k)]) = crs.values[static_cast<std::size_t>(k)];
  Eigen::Index start = 0;
  for (ceres::ResidualBlockId id : eo.residual_blocks) {
    out.segment_starts.push_back(start);
    start += problem.GetCostFunctionForResidualBlock(id)->num_residuals();
  }
  out.ok = true;
  return out;
}

// Σ over segments of Σₖ a(k) b(k − τ)ᵀ for rows k, k − τ in the same segment.
Eigen::MatrixXd lagged_cross(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, const std::vector<Eigen::Index>& starts,
                             Eigen::Index lag) {
  Eigen::MatrixXd s = Eigen::MatrixXd::Zero(a.cols(), b.cols());
  for (std::size_t i = 0; i < starts.size(); ++i) {
    const Eigen::Index lo = starts[i], hi = i + 1 < starts.size() ? starts[i + 1] : a.rows();
    const Eigen::Index len = hi - lo - lag;
    if (len > 0) s.noalias() += a.middleRows(lo + lag, len).transpose() * b.middleRows(lo, len);
  }
  return s;
}

// Ljung–Box Q over M = min(25, N/5) lags of the pooled residual autocorrelation, against the
// χ²(M) 99 % quantile (Ljung & Box 1978, Biometrika 65:297–303; as ident/residuals.hpp).
bool residual_is_white(const Eigen::VectorXd& e, const std::vector<Eigen::Index>& starts) {
  const auto n = e.size();
  const Eigen::Index m = std::min<Eigen::Index>(25, n / 5);
  const double r0 = e.squaredNorm();
  if (m < 1 || !(r0 > 0.0)) return true;
  const Eigen::MatrixXd col = e;
  double q = 0.0;
  for (Eigen::Index lag = 1; lag <= m; ++lag) {
    const double r = lagged_cross(col, col, starts, lag)(0, 0) / r0;
    q += r * r / static_cast<double>(n - lag);
  }
  q *= static_cast<double>(n) * static_cast<double>(n + 2);
  return q <= distributions::chi_squared_quantile(static_cast<double>(m), 0.99);
}

// Bartlett-kernel bandwidth from AR(1) fits to each score series gₐ(k) = Jₖₐ eₖ (Andrews 1991,
// "Heteroskedasticity and autocorrelation consistent covariance matrix estimation",
// Econometrica 59:817–858, Eq. 6.4 and §6: S_T = 1.1447 (α(1) T)^(1/3), ρ restricted to ±0.97).
Eigen::Index bartlett_bandwidth(const Eigen::MatrixXd& g, const std::vector<Eigen::Index>& starts) {
  double num = 0.0, den = 0.0;
  for (Eigen::Index a = 0; a < g.cols(); ++a) {
    const Eigen::MatrixXd col = g.col(a);
    const double c0 = col.squaredNorm(), c1 = lagged_cross(col, col, starts, 1)(0, 0);
    if (!(c0 > 0.0)) continue;
    const double rho = std::clamp(c1 / c0, -0.97, 0.97);
    const double s2 = c0 * (1.0 - rho * rho) / static_cast<double>(g.rows());  // innovation variance
    num += 4.0 * rho * rho * s2 * s2 / (std::pow(1.0 - rho, 6) * (1.0 + rho) * (1.0 + rho));
    den += s2 * s2 / std::pow(1.0 - rho, 4);
  }
  if (!(den > 0.0)) return 0;
  const double bw = 1.1447 * std::cbrt(num / den * static_cast<double>(g.rows()));
  return std::min<Eigen::Index>(static_cast<Eigen::Index>(std::floor(bw)), g.rows() / 4);
}

// (JᵀJ)⁻¹ of column-scaled J (see covariance.hpp), or NaN; also returns the scale.
Eigen::MatrixXd scaled_inverse(const Eigen::MatrixXd& j, Eigen::VectorXd& scale) {
  const auto cols = j.cols();
  const Eigen::MatrixXd nan = Eigen::MatrixXd::Constant(cols, cols, std::numeric_limits<double>::quiet_NaN());
  scale = j.colwise().norm().transpose();
  for (Eigen::Index i = 0; i < scale.size(); ++i) {
    if (!(scale(i) > 0.0)) return nan;  // a parameter the residuals do not depend on
    scale(i) = 1.0 / scale(i);
  }
  const Eigen::MatrixXd js = j * scale.asDiagonal();
  const linalg::SingularValueDecomposition svd = linalg::svd(js, linalg::SvdMethod::jacobi, false, true);
  const Eigen::VectorXd& s = svd.values;
  if (s.size() == 0 || !(s(s.size() - 1) > 1e-9 * s(0))) return nan;
  const Eigen::MatrixXd& v = svd.v;
  return v * s.cwiseAbs2().cwiseInverse().asDiagonal() * v.transpose();
}

}  // namespace

Eigen::MatrixXd parameter_covariance(ceres::Problem& problem, const std::vector<double*>& blocks, double sigma2,
                                     std::size_t free_parameters) {
  int cols = 0;
  for (double* b : blocks) cols += problem.ParameterBlockSize(b);
  const Evaluated ev = evaluate(problem, blocks);
  if (!ev.ok) return Eigen::MatrixXd::Constant(cols, cols, std::numeric_limits<double>::quiet_NaN());
  Eigen::VectorXd scale;
  const Eigen::MatrixXd inv = scaled_inverse(ev.jacobian, scale);
  if (!inv.allFinite() || residual_is_white(ev.residuals, ev.segment_starts))
    return scale.asDiagonal() * inv * scale.asDiagonal() * sigma2;
  // Coloured residual: the sandwich (JᵀJ)⁻¹ Ŝ (JᵀJ)⁻¹ with the Newey–West (Bartlett) estimate
  // Ŝ = Γ(0) + Σ_{τ=1}^{L} (1 − τ/(L+1)) (Γ(τ) + Γ(τ)ᵀ) of the score gₖ = Jₖ eₖ (Newey & West 1987,
  // Econometrica 55:703–708; for output error, Ljung 1999 System Identification Eq. 9.64), times
  // N/(N − p) as σ² above.
  const Eigen::MatrixXd g = (ev.jacobian * scale.asDiagonal()).array().colwise() * ev.residuals.array();
  const Eigen::Index lags = bartlett_bandwidth(g, ev.segment_starts);
  Eigen::MatrixXd s = lagged_cross(g, g, ev.segment_starts, 0);
  for (Eigen::Index lag = 1; lag <= lags; ++lag) {
    const Eigen::MatrixXd gamma = lagged_cross(g, g, ev.segment_starts, lag);
    s += (1.0 - static_cast<double>(lag) / static_cast<double>(lags + 1)) * (gamma + gamma.transpose());
  }
  const auto n = static_cast<double>(ev.residuals.size());
  const double dof = n > static_cast<double>(free_parameters) ? n / (n - static_cast<double>(free_parameters))
                                                              : std::numeric_limits<double>::quiet_NaN();
  return scale.asDiagonal() * (inv * s * inv) * scale.asDiagonal() * dof;
}

}  // namespace clearshape::ident::detail
