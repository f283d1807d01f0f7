#include "clearshape/ident/subspace.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"

namespace clearshape::ident {

namespace {

double rms(std::span<const double> v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

// Block Hankel (SISO): H(r, c) = v[first + r + c], rows × cols.
Eigen::MatrixXd hankel(std::span<const double> v, std::size_t first, std::size_t rows, std::size_t cols) {
  Eigen::MatrixXd h(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) h(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = v[first + r + c];
  return h;
}

// A and C from an extended observability matrix Γ (rows = horizon): C = Γ₀, A = Γ↑⁺ Γ↓.
void shift_invariance(const Eigen::MatrixXd& gamma, Eigen::MatrixXd& a, Eigen::RowVectorXd& c) {
  const Eigen::Index i = gamma.rows();
  c = gamma.row(0);
  a = gamma.topRows(i - 1).completeOrthogonalDecomposition().solve(gamma.bottomRows(i - 1));
}

// The horizon i (block rows): options.block_rows or max(2n, 10); checked against the record.
std::size_t horizon(const Experiment& experiment, std::size_t order, const SubspaceOptions& options) {
  const std::size_t n_samples = experiment.size();
  const std::size_t i = options.block_rows > 0 ? options.block_rows : std::max<std::size_t>(2 * order, 10);
  if (i <= order) {
    throw_invalid("n4sid block_rows", static_cast<double>(i), "> order (" + std::to_string(order) + ")",
                  "The horizon must exceed the model order.");
  }
  if (n_samples < 2 * i + 2 * order + 10) {
    throw InvalidArgument("n4sid: experiment \"" + experiment.name + "\" has " + std::to_string(n_samples) +
                          " samples; a horizon of " + std::to_string(i) + " and order " + std::to_string(order) +
                          " need at least " + std::to_string(2 * i + 2 * order + 10) + ". Use a longer record.");
  }
  return i;
}

// u and y scaled to unit RMS for conditioning; the scales are undone at the end.
struct ScaledData {
  std::vector<double> u, y;
  double su = 1.0, sy = 1.0;
};

ScaledData scaled(const Experiment& experiment) {
  const std::size_t n_samples = experiment.size();
  ScaledData s;
  s.su = rms(experiment.input) > 0.0 ? rms(experiment.input) : 1.0;
  s.sy = rms(experiment.output) > 0.0 ? rms(experiment.output) : 1.0;
  s.u.reserve(n_samples);
  s.y.reserve(n_samples);
  for (std::size_t k = 0; k < n_samples; ++k) {
    s.u.push_back(experiment.input[k] / s.su);
    s.y.push_back(experiment.output[k] / s.sy);
  }
  return s;
}

// A matrix whose left singular vectors span the extended observability matrix Γᵢ.
Eigen::MatrixXd observability_basis(const ScaledData& s, std::size_t i, SubspaceMethod method) {
  const std::size_t j = s.u.size() - 2 * i + 1;
  const auto ii = static_cast<Eigen::Index>(i);
  const Eigen::MatrixXd up = hankel(s.u, 0, i, j), uf = hankel(s.u, i, i, j);
  const Eigen::MatrixXd yp = hankel(s.y, 0, i, j), yf = hankel(s.y, i, i, j);
  Eigen::MatrixXd wp(2 * ii, static_cast<Eigen::Index>(j));
  wp << up, yp;
  if (method == SubspaceMethod::n4sid) {
    // Yf ≈ Lw Wp + Lu Uf (least squares, QR of the regressor); the oblique projection of Yf
    // along Uf onto Wp is Oᵢ = Lw Wp (Van Overschee & De Moor 1996, Thm. 2), whose left
    // singular vectors are those of Lw Rᵀ with Wpᵀ = Q R.
    Eigen::MatrixXd z(3 * ii, static_cast<Eigen::Index>(j));
    z << up, yp, uf;
    const Eigen::MatrixXd theta = z.transpose().colPivHouseholderQr().solve(yf.transpose()).transpose();
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(wp.transpose());
    const Eigen::MatrixXd r = qr.matrixQR().topRows(2 * ii).triangularView<Eigen::Upper>();
    return theta.leftCols(2 * ii) * r.transpose();
  }
  // PO-MOESP (Verhaegen 1994): LQ of [Uf; Wp; Yf] = L Qᵀ; the block L32 (Yf rows, Wp columns)
  // is Yf projected orthogonally to Uf and correlated with the past: its column space is Γᵢ.
  Eigen::MatrixXd h(4 * ii, static_cast<Eigen::Index>(j));
  h << uf, wp, yf;
  Eigen::HouseholderQR<Eigen::MatrixXd> qr(h.transpose());
  const Eigen::MatrixXd l = qr.matrixQR().topRows(4 * ii).triangularView<Eigen::Upper>().transpose();
  return l.block(3 * ii, ii, ii, 2 * ii);
}

// x0, B and D of the scaled data, given A and C.
struct InputTerms {
  Eigen::VectorXd x0, b;
  double d = 0.0;
};

// Least squares on y[k] = C Aᵏ x0 + Σ_{m<k} C A^(k−1−m) B u[m] + D u[k].
InputTerms input_terms(const Eigen::MatrixXd& a, const Eigen::RowVectorXd& c, const ScaledData& s,
                       const SubspaceOptions& options) {
  const std::size_t n_samples = s.u.size();
  const Eigen::Index n = a.rows();
  const bool with_x0 = options.estimate_initial_state;
  const Eigen::Index cols = (with_x0 ? n : 0) + n + (options.feedthrough ? 1 : 0);
  Eigen::MatrixXd phi(static_cast<Eigen::Index>(n_samples), cols);
  Eigen::RowVectorXd cak = c;                        // C Aᵏ
  Eigen::MatrixXd xb = Eigen::MatrixXd::Zero(n, n);  // state of (A, e_l) driven by u
  for (std::size_t k = 0; k < n_samples; ++k) {
    const auto kk = static_cast<Eigen::Index>(k);
    Eigen::Index col = 0;
    if (with_x0) {
      phi.block(kk, 0, 1, n) = cak;
      col += n;
    }
    phi.block(kk, col, 1, n) = c * xb;
    col += n;
    if (options.feedthrough) phi(kk, col) = s.u[k];
    cak = cak * a;
    xb = a * xb;
    xb.diagonal().array() += s.u[k];  // + e_l u[k] for every column l
  }
  const Eigen::VectorXd yv = Eigen::Map<const Eigen::VectorXd>(s.y.data(), static_cast<Eigen::Index>(n_samples));
  const Eigen::VectorXd sol = phi.colPivHouseholderQr().solve(yv);
  InputTerms out;
  Eigen::Index col = 0;
  out.x0 = Eigen::VectorXd::Zero(n);
  if (with_x0) {
    out.x0 = sol.head(n);
    col += n;
  }
  out.b = sol.segment(col, n);
  col += n;
  out.d = options.feedthrough ? sol(col) : 0.0;
  return out;
}

}  // namespace

namespace {

// The order-n model from the SVD of the observability basis (Γ = U₁ S₁^½; A, C by shift
// invariance; B, D, x0 by least squares). Throws RuntimeError when singular value n is zero.
SubspaceModel subspace_model(const linalg::SingularValueDecomposition& svd, const ScaledData& s, std::size_t order,
                             const Experiment& experiment, const SubspaceOptions& options) {
  SubspaceModel out;
  for (Eigen::Index k = 0; k < svd.values.size(); ++k) out.singular_values.push_back(svd.values(k));
  const auto n = static_cast<Eigen::Index>(order);
  if (!(svd.values(n - 1) > 1e-12 * svd.values(0))) {
    throw RuntimeError("subspace identification: the data do not support order " + std::to_string(order) +
                       " (singular value " + std::to_string(n) + " is zero); choose a lower order or a richer input.");
  }
  const Eigen::MatrixXd gamma = svd.u.leftCols(n) * svd.values.head(n).cwiseSqrt().asDiagonal();
  Eigen::MatrixXd a;
  Eigen::RowVectorXd c;
  shift_invariance(gamma, a, c);
  const InputTerms t = input_terms(a, c, s, options);
  out.model.a = a;
  out.model.b = t.b / s.su;
  out.model.c = c * s.sy;
  out.model.d = Eigen::MatrixXd::Constant(1, 1, t.d * s.sy / s.su);
  out.model.sample_time_s = experiment.sample_time_s;
  out.model.hold = lti::Hold::zoh;
  out.initial_state = t.x0;
  return out;
}

// ERA's balanced factors truncated at `order` (capped at the numerical rank, > 1e-10·σ₁).
FreeResponseModel era_model(const linalg::SingularValueDecomposition& svd, std::size_t order) {
  FreeResponseModel out;
  for (Eigen::Index k = 0; k < svd.values.size(); ++k) out.singular_values.push_back(svd.values(k));
  Eigen::Index n = 0;
  while (n < static_cast<Eigen::Index>(order) && svd.values(n) > 1e-10 * svd.values(0)) ++n;
  if (n == 0) throw RuntimeError("era: the response is identically zero; there is nothing to identify.");
  const Eigen::VectorXd s_half = svd.values.head(n).cwiseSqrt();
  const Eigen::MatrixXd gamma = svd.u.leftCols(n) * s_half.asDiagonal();  // balanced factors
  const Eigen::MatrixXd x = s_half.asDiagonal() * svd.v.leftCols(n).transpose();
  shift_invariance(gamma, out.a, out.c);
  out.x0 = x.col(0);
  return out;
}

}  // namespace

SubspaceModel n4sid(const Experiment& experiment, std::size_t order, const SubspaceOptions& options) {
  validate(experiment);
  if (order < 1) throw_invalid("n4sid order", 0.0, ">= 1");
  const std::size_t i = horizon(experiment, order, options);
  const ScaledData s = scaled(experiment);
  const auto svd = linalg::svd(observability_basis(s, i, options.method), linalg::SvdMethod::jacobi, true, false);
  return subspace_model(svd, s, order, experiment, options);
}

std::vector<SubspaceModel> n4sid_orders(const Experiment& experiment, std::size_t min_order, std::size_t max_order,
                                        const SubspaceOptions& options) {
  validate(experiment);
  if (min_order < 1 || max_order < min_order) throw_invalid("n4sid min_order", static_cast<double>(min_order), ">= 1 and <= max_order");
  const std::size_t i = horizon(experiment, max_order, options);
  const ScaledData s = scaled(experiment);
  const auto svd = linalg::svd(observability_basis(s, i, options.method), linalg::SvdMethod::jacobi, true, false);
  std::vector<SubspaceModel> out;
  for (std::size_t n = min_order; n <= max_order; ++n) {
    try {
      out.push_back(subspace_model(svd, s, n, experiment, options));
    } catch (const RuntimeError&) {  // the data do not support this order: an empty model
      out.emplace_back();
    }
  }
  return out;
}

namespace {

// era's checks; returns the Hankel rows.
std::size_t era_rows(std::span<const double> response, std::size_t order, std::size_t rows) {
  const std::size_t n_samples = response.size();
  if (order < 1) throw_invalid("era order", 0.0, ">= 1");
  const std::size_t r = rows > 0 ? rows : std::min(n_samples / 3, std::max<std::size_t>(4 * order, 40));
  if (r <= order || n_samples < 2 * r) {
    throw InvalidArgument("era: a free response of " + std::to_string(n_samples) + " samples cannot support order " +
                          std::to_string(order) + " with " + std::to_string(r) +
                          " Hankel rows (needs rows > order and N >= 2·rows); use a longer record or a lower order.");
  }
  for (std::size_t k = 0; k < n_samples; ++k) {
    if (!std::isfinite(response[k])) {
      throw InvalidArgument("era: sample " + std::to_string(k) + " of the response is not finite; repair the record.");
    }
  }
  return r;
}

}  // namespace

FreeResponseModel era(std::span<const double> response, std::size_t order, std::size_t rows) {
  const std::size_t r = era_rows(response, order, rows);
  const std::size_t n_samples = response.size();
  const std::size_t cols = n_samples - r + 1;
  const Eigen::MatrixXd h = hankel(response, 0, r, cols);  // H(a, b) = y[a + b] = C A^(a+b) x0
  const auto svd = linalg::svd(h, linalg::SvdMethod::divide_and_conquer, true, true);
  // The order is capped at the numerical rank of the Hankel matrix (an exact response of fewer
  // modes than asked for).
  return era_model(svd, order);
}

std::vector<FreeResponseModel> era_orders(std::span<const double> response, std::size_t min_order, std::size_t max_order,
                                          std::size_t rows) {
  if (min_order < 1 || max_order < min_order) throw_invalid("era min_order", static_cast<double>(min_order), ">= 1 and <= max_order");
  const std::size_t r = era_rows(response, max_order, rows);
  const Eigen::MatrixXd h = hankel(response, 0, r, response.size() - r + 1);
  const auto svd = linalg::svd(h, linalg::SvdMethod::divide_and_conquer, true, true);
  std::vector<FreeResponseModel> out;
  for (std::size_t n = min_order; n <= max_order; ++n) out.push_back(era_model(svd, n));
  return out;
}

}  // namespace clearshape::ident
