#include "process_sampling.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include <ceres/jet.h>

#include "clearshape/core/linalg.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::ident::detail {

namespace {

constexpr int kMaxParameters = 8;
using Jet = ceres::Jet<double, kMaxParameters>;
template <class T>
using Mat = Eigen::Matrix<T, Eigen::Dynamic, Eigen::Dynamic>;

struct Indices {
  int kp = -1;
  std::array<int, 3> tp{-1, -1, -1};
  int tw = -1, zeta = -1, td = -1, tz = -1;
};

Indices indices(const lti::ProcessStructure& s) {
  Indices ix;
  const auto names = s.parameter_names();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const int k = static_cast<int>(i);
    if (names[i] == "Kp") ix.kp = k;
    if (names[i] == "Tp1") ix.tp[0] = k;
    if (names[i] == "Tp2") ix.tp[1] = k;
    if (names[i] == "Tp3") ix.tp[2] = k;
    if (names[i] == "Tw") ix.tw = k;
    if (names[i] == "Zeta") ix.zeta = k;
    if (names[i] == "Td") ix.td = k;
    if (names[i] == "Tz") ix.tz = k;
  }
  return ix;
}

template <class T>
struct Section {
  Mat<T> a, b, c, d;
  enum Kind { integrator, first_order, pair } kind = first_order;
};

template <class T>
Section<T> scalar_section(const T& a, const T& b, typename Section<T>::Kind kind) {
  Section<T> s;
  s.a = Mat<T>::Constant(1, 1, a);
  s.b = Mat<T>::Constant(1, 1, b);
  s.c = Mat<T>::Constant(1, 1, T(1.0));
  s.d = Mat<T>::Constant(1, 1, T(0.0));
  s.kind = kind;
  return s;
}

// The cascade of lti::ProcessModel::state_space(), for any scalar type.
template <class T>
void realize_t(const lti::ProcessStructure& s, const Indices& ix, const std::vector<T>& v, Mat<T>& a,
               Mat<T>& b, Mat<T>& c, Mat<T>& d) {
  std::vector<Section<T>> sections;
  if (s.integrator) sections.push_back(scalar_section(T(0.0), T(1.0), Section<T>::integrator));  // 1/s
  for (int tp_index : ix.tp) {
    if (tp_index < 0) continue;
    const T& tp = v[static_cast<std::size_t>(tp_index)];  // 1/(1 + Tp s): ẋ = (u − x)/Tp
    sections.push_back(scalar_section(T(-1.0) / tp, T(1.0) / tp, Section<T>::first_order));
  }
  if (s.underdamped) {  // 1/(1 + 2ζTw s + Tw² s²), x1 = y, x2 = Tw ẏ (Eq. 4.2)
    const T& tw = v[static_cast<std::size_t>(ix.tw)];
    const T& z = v[static_cast<std::size_t>(ix.zeta)];
    Section<T> p;
    p.kind = Section<T>::pair;
    p.a.resize(2, 2);
    p.a << T(0.0), T(1.0) / tw, T(-1.0) / tw, T(-2.0) * z / tw;
    p.b.resize(2, 1);
    p.b << T(0.0), T(1.0) / tw;
    p.c.resize(1, 2);
    p.c << T(1.0), T(0.0);
    p.d = Mat<T>::Constant(1, 1, T(0.0));
    sections.push_back(p);
  }
  const T kp = v[static_cast<std::size_t>(ix.kp)];
  const T tz = s.zero ? v[static_cast<std::size_t>(ix.tz)] : T(0.0);
  if (sections.empty()) {  // static gain Kp
    a.resize(0, 0);
    b.resize(0, 1);
    c.resize(1, 0);
    d = Mat<T>::Constant(1, 1, kp);
    return;
  }
  Section<T>& last = sections.back();  // y = Kp (x + Tz ẋ) of the last section's output x
  if (last.kind == Section<T>::pair) {
    last.c(0, 1) = tz / v[static_cast<std::size_t>(ix.tw)];
  } else if (last.kind == Section<T>::first_order) {
    const T inv_tp = -last.a(0, 0);
    last.c(0, 0) = T(1.0) - tz * inv_tp;
    last.d(0, 0) = tz * inv_tp;
  } else {
    last.d(0, 0) = tz;
  }
  last.c *= kp;
  last.d *= kp;
  a = sections.front().a;
  b = sections.front().b;
  c = sections.front().c;
  d = sections.front().d;
  for (std::size_t i = 1; i < sections.size(); ++i) {  // series: [A1 0; B2 C1 A2], [B1; B2 D1], [D2 C1, C2], D2 D1
    const Section<T>& s2 = sections[i];
    const Eigen::Index n1 = a.rows(), n2 = s2.a.rows();
    Mat<T> na = Mat<T>::Constant(n1 + n2, n1 + n2, T(0.0));
    na.topLeftCorner(n1, n1) = a;
    na.bottomLeftCorner(n2, n1) = s2.b * c;
    na.bottomRightCorner(n2, n2) = s2.a;
    Mat<T> nb(n1 + n2, 1);
    nb.topRows(n1) = b;
    nb.bottomRows(n2) = s2.b * d;
    Mat<T> nc(1, n1 + n2);
    nc.leftCols(n1) = s2.d * c;
    nc.rightCols(n2) = s2.c;
    Mat<T> nd = s2.d * d;
    a = std::move(na);
    b = std::move(nb);
    c = std::move(nc);
    d = std::move(nd);
  }
}

struct Piece {
  Eigen::MatrixXd phi;
  Eigen::VectorXd gamma, lambda;
  Eigen::MatrixXd phi_h;  // d/dh
  Eigen::VectorXd gamma_h, lambda_h;
  std::vector<Eigen::MatrixXd> dphi;  // per parameter
  std::vector<Eigen::VectorXd> dgamma, dlambda;
};

// Exact integrals over a hold interval of length h (see hold_integrals in lti):
// Φ = e^(Ah), Γ = ∫₀ʰ e^(Aσ)dσ b, Λ = (1/h)∫₀ʰ e^(A(h−σ)) b σ dσ, from expm of G·h with
// G = [A b 0; 0 0 1; 0 0 0] (Van Loan 1978); Λ = J/h with J the (n, n+1) block.
Piece make_piece(const Realization& r, double h, bool derivatives, bool need_h) {
  const Eigen::Index n = r.a.rows();
  const Eigen::Index m = n + 2;
  Eigen::MatrixXd g = Eigen::MatrixXd::Zero(m, m);
  g.topLeftCorner(n, n) = r.a;
  g.block(0, n, n, 1) = r.b;
  g(n, n + 1) = 1.0;
  Piece p;
  const std::size_t count = derivatives ? r.da.size() : 0;
  p.dphi.assign(count, Eigen::MatrixXd::Zero(n, n));
  p.dgamma.assign(count, Eigen::VectorXd::Zero(n));
  p.dlambda.assign(count, Eigen::VectorXd::Zero(n));
  if (h == 0.0) {
    p.phi = Eigen::MatrixXd::Identity(n, n);
    p.gamma = Eigen::VectorXd::Zero(n);
    p.lambda = Eigen::VectorXd::Zero(n);
    if (need_h) {  // derivatives at h = 0: A, b, and Λ ≈ b h/2 → b/2
      p.phi_h = r.a;
      p.gamma_h = r.b.col(0);
      p.lambda_h = 0.5 * r.b.col(0);
    }
    return p;
  }
  const Eigen::MatrixXd gh = g * h;
  const Eigen::MatrixXd e = linalg::expm(gh);  // Padé scaling and squaring (Higham 2005)
  p.phi = e.topLeftCorner(n, n);
  p.gamma = e.block(0, n, n, 1);
  const Eigen::VectorXd j = e.block(0, n + 1, n, 1);
  p.lambda = j / h;
  if (need_h) {
    const Eigen::MatrixXd ge = g * e;  // d/dh e^(Gh) = G e^(Gh)
    p.phi_h = ge.topLeftCorner(n, n);
    p.gamma_h = ge.block(0, n, n, 1);
    p.lambda_h = ge.block(0, n + 1, n, 1) / h - j / (h * h);
  }
  for (std::size_t i = 0; i < count; ++i) {
    if (r.da[i].isZero(0.0) && r.db[i].isZero(0.0)) continue;
    Eigen::MatrixXd big = Eigen::MatrixXd::Zero(2 * m, 2 * m);  // [[G h, dG h], [0, G h]] (Van Loan)
    big.topLeftCorner(m, m) = gh;
    big.bottomRightCorner(m, m) = gh;
    big.block(0, m, n, n) = r.da[i] * h;
    big.block(0, m + n, n, 1) = r.db[i] * h;
    const Eigen::MatrixXd eb = linalg::expm(big);
    p.dphi[i] = eb.block(0, m, n, n);
    p.dgamma[i] = eb.block(0, m + n, n, 1);
    p.dlambda[i] = eb.block(0, m + n + 1, n, 1) / h;
  }
  return p;
}

struct PieceView {
  const Eigen::MatrixXd* phi;
  const Eigen::VectorXd* gamma;
  const Eigen::VectorXd* lambda;
};

// Taps of the sampled model from the two pieces (the relations of lti::SampledModel).
void compose(const PieceView& p1, const PieceView& p2, double d, double f, lti::Hold hold, Eigen::MatrixXd& phi,
             Eigen::MatrixXd& taps, Eigen::Vector3d& h) {
  const Eigen::Index n = p1.phi->rows();
  phi = (*p2.phi) * (*p1.phi);
  taps = Eigen::MatrixXd::Zero(n, 3);
  h.setZero();
  if (hold == lti::Hold::zoh) {
    taps.col(2) = (*p2.phi) * (*p1.gamma);  // u[k−2−d] held over the first part
    taps.col(1) = *p2.gamma;                // u[k−1−d] over the second
    h(f > 0.0 ? 1 : 0) = d;
  } else {
    const Eigen::VectorXd g1 = *p1.gamma - *p1.lambda;
    const Eigen::VectorXd g2 = *p2.gamma - *p2.lambda;
    taps.col(2) = f * ((*p2.phi) * g1);
    taps.col(1) = (*p2.phi) * ((1.0 - f) * g1 + *p1.lambda) + g2 + f * (*p2.lambda);
    taps.col(0) = (1.0 - f) * (*p2.lambda);
    h(1) = f * d;
    h(0) = (1.0 - f) * d;
  }
}

// Product-rule derivative of compose() along one direction (dp1, dp2, df, dd).
void compose_derivative(const PieceView& p1, const PieceView& dp1, const PieceView& p2, const PieceView& dp2,
                        double d, double dd, double f, double df, lti::Hold hold, Eigen::MatrixXd& dphi,
                        Eigen::MatrixXd& dtaps, Eigen::Vector3d& dh) {
  const Eigen::Index n = p1.phi->rows();
  dphi = (*dp2.phi) * (*p1.phi) + (*p2.phi) * (*dp1.phi);
  dtaps = Eigen::MatrixXd::Zero(n, 3);
  dh.setZero();
  if (hold == lti::Hold::zoh) {
    dtaps.col(2) = (*dp2.phi) * (*p1.gamma) + (*p2.phi) * (*dp1.gamma);
    dtaps.col(1) = *dp2.gamma;
    dh(f > 0.0 ? 1 : 0) = dd;
  } else {
    const Eigen::VectorXd g1 = *p1.gamma - *p1.lambda;
    const Eigen::VectorXd dg1 = *dp1.gamma - *dp1.lambda;
    const Eigen::VectorXd dg2 = *dp2.gamma - *dp2.lambda;
    dtaps.col(2) = df * ((*p2.phi) * g1) + f * ((*dp2.phi) * g1 + (*p2.phi) * dg1);
    dtaps.col(1) = (*dp2.phi) * ((1.0 - f) * g1 + *p1.lambda) +
                   (*p2.phi) * (-df * g1 + (1.0 - f) * dg1 + *dp1.lambda) + dg2 + df * (*p2.lambda) +
                   f * (*dp2.lambda);
    dtaps.col(0) = -df * (*p2.lambda) + (1.0 - f) * (*dp2.lambda);
    dh(1) = df * d + f * dd;
    dh(0) = -df * d + (1.0 - f) * dd;
  }
}

// ---------------------------------------------------------------- sensitivity kernel

// The sampled model and its derivatives along the fitted directions in flat arrays sized for
// order NS (row-major Φ, taps G as n × 3, C, H), read by the kernel's inner loops.
template <int NS>
struct KernelTables {
  static constexpr int n = NS;
  static constexpr int nn = n * n + 1;
  std::array<double, nn> phi{};
  std::array<double, 3 * n + 1> g{};
  std::array<double, n + 1> c{};
  std::array<double, 3> h{};
  std::array<std::array<double, nn>, kMaxParameters> dphi{};
  std::array<std::array<double, 3 * n + 1>, kMaxParameters> dg{};
  std::array<std::array<double, n + 1>, kMaxParameters> dc{};
  std::array<std::array<double, 3>, kMaxParameters> dh{};
  std::array<double, kMaxParameters> scale{};
};

template <int NS>
void load_tables(const KernelInput& in, int np, KernelTables<NS>& t) noexcept {
  constexpr int n = NS;
  const Sampled& m = *in.model;
  t.h = {m.h(0), m.h(1), m.h(2)};
  for (int i = 0; i < n; ++i) {
    t.c[i] = m.c(i);
    for (int l = 0; l < n; ++l) t.phi[i * n + l] = m.phi(i, l);
    for (int j = 0; j < 3; ++j) t.g[i * 3 + j] = m.taps(i, j);
  }
  for (int p = 0; p < np; ++p) {
    const auto q = static_cast<std::size_t>(in.directions[static_cast<std::size_t>(p)]);
    t.scale[static_cast<std::size_t>(p)] = in.scale[static_cast<std::size_t>(p)];
    for (int j = 0; j < 3; ++j) t.dh[p][j] = m.dh[q](j);
    for (int i = 0; i < n; ++i) {
      t.dc[p][i] = m.dc[q](i);
      for (int l = 0; l < n; ++l) t.dphi[p][i * n + l] = m.dphi[q](i, l);
      for (int j = 0; j < 3; ++j) t.dg[p][i * 3 + j] = m.dtaps[q](i, j);
    }
  }
}

// What the kernel computes besides the output: np parameter directions, ∂/∂x0, ∂/∂u0, ∂/∂y0.
struct KernelShape {
  int np = 0;
  bool dx0 = false, du0 = false, dy0 = false;
  std::size_t cols = 0;  ///< Jacobian columns
  int zu_block = 0;      ///< state block of ∂x/∂u0 (after x and the np parameter blocks)
};

// The input at lags 0, 1, 2 of one sample (u[k−d], u[k−d−1], u[k−d−2]).
struct Lags {
  double l0, l1, l2;
};

// One step of the state blocks [x | z_0 … z_(np−1) | zu] from `cur` into `nxt`; vb: the
// real-sample indicator at the same lags as the input (∂u/∂u0 = −1 there).
template <int NS>
[[gnu::always_inline]] inline void advance_states(const KernelTables<NS>& t, const KernelShape& ks,
                                                  const double* __restrict cur, double* __restrict nxt, const Lags& u,
                                                  const double* vb) noexcept {
  constexpr int n = NS;
  const int np = ks.np;
  const double* x = cur;
  for (int i = 0; i < n; ++i) {  // x[k] = Φ x[k−1] + Σ Gⱼ u[k−d−j]
    double s = t.g[i * 3] * u.l0 + t.g[i * 3 + 1] * u.l1 + t.g[i * 3 + 2] * u.l2;
    for (int l = 0; l < n; ++l) s += t.phi[i * n + l] * x[l];
    nxt[i] = s;
  }
  for (int p = 0; p < np; ++p) {  // ∂x[k] = Φ ∂x[k−1] + ∂Φ x[k−1] + Σ ∂Gⱼ u[k−d−j]
    const double* z = cur + (1 + p) * n;
    double* zn = nxt + (1 + p) * n;
    for (int i = 0; i < n; ++i) {
      double s = t.dg[p][i * 3] * u.l0 + t.dg[p][i * 3 + 1] * u.l1 + t.dg[p][i * 3 + 2] * u.l2;
      for (int l = 0; l < n; ++l) s += t.phi[i * n + l] * z[l] + t.dphi[p][i * n + l] * x[l];
      zn[i] = s;
    }
  }
  if (ks.du0) {
    const double* zu = cur + ks.zu_block * n;
    double* zun = nxt + ks.zu_block * n;
    for (int i = 0; i < n; ++i) {
      double s = -(t.g[i * 3] * vb[2] + t.g[i * 3 + 1] * vb[1] + t.g[i * 3 + 2] * vb[0]);
      for (int l = 0; l < n; ++l) s += t.phi[i * n + l] * zu[l];
      zun[i] = s;
    }
  }
}

// r ← r Φ: the row C Φᵏ of the ∂y/∂x0 columns.
template <int NS>
[[gnu::always_inline]] inline void advance_initial_state_row(const KernelTables<NS>& t, std::array<double, NS + 1>& r) noexcept {
  constexpr int n = NS;
  std::array<double, n + 1> rn{};
  for (int l = 0; l < n; ++l) {
    double s = 0.0;
    for (int i = 0; i < n; ++i) s += r[i] * t.phi[i * n + l];
    rn[l] = s;
  }
  r = rn;
}

// One row of the Jacobian: ∂y[k] along each direction (scaled), C Φᵏ, ∂y/∂u0, ∂y/∂y0.
template <int NS>
[[gnu::always_inline]] inline void jacobian_row(const KernelTables<NS>& t, const KernelShape& ks,
                                                const double* __restrict cur, const std::array<double, NS + 1>& r,
                                                const Lags& u, const double* vb, double* __restrict row) noexcept {
  constexpr int n = NS;
  const int np = ks.np;
  const double* x = cur;
  for (int p = 0; p < np; ++p) {
    const double* z = cur + (1 + p) * n;
    double s = t.dh[p][0] * u.l0 + t.dh[p][1] * u.l1 + t.dh[p][2] * u.l2;
    for (int i = 0; i < n; ++i) s += t.c[i] * z[i] + t.dc[p][i] * x[i];
    row[p] = t.scale[static_cast<std::size_t>(p)] * s;
  }
  std::size_t col = static_cast<std::size_t>(np);
  if (ks.dx0) {
    for (int l = 0; l < n; ++l) row[col++] = r[l];
  }
  if (ks.du0) {
    const double* zu = cur + ks.zu_block * n;
    double s = -(t.h[0] * vb[2] + t.h[1] * vb[1] + t.h[2] * vb[0]);
    for (int i = 0; i < n; ++i) s += t.c[i] * zu[i];
    row[col++] = s;
  }
  if (ks.dy0) row[col] = 1.0;
}

// Input with d + 2 leading zeros (the history before the start): lag j of sample k is
// padded[k + 2 − j]; the same for the indicator of real samples (∂u/∂u0 = −1 there).
void pad_input(std::span<const double> input, std::size_t d, std::vector<double>& padded, std::vector<double>& valid) {
  padded.assign(input.size() + d + 2, 0.0);
  valid.assign(input.size() + d + 2, 0.0);
  for (std::size_t k = 0; k < input.size(); ++k) {
    padded[k + d + 2] = input[k];
    valid[k + d + 2] = 1.0;
  }
}

template <int NS>
bool run_kernel(const KernelInput& in, double* out, double* jac) {
  constexpr int n = NS;
  const std::size_t count = in.input.size();
  KernelShape ks;
  ks.np = jac != nullptr ? static_cast<int>(in.directions.size()) : 0;
  ks.dx0 = jac != nullptr && in.d_x0;
  ks.du0 = jac != nullptr && in.d_u0;
  ks.dy0 = jac != nullptr && in.d_y0;
  ks.cols = jac != nullptr ? jacobian_columns(in) : 0;
  ks.zu_block = 1 + ks.np;
  KernelTables<NS> t;
  load_tables(in, ks.np, t);
  std::vector<double> padded, valid;
  pad_input(in.input, in.model->delay_samples, padded, valid);
  // State blocks: [x | z_0 … z_(np−1) | zu], each n wide; r = C Φᵏ for the x0 columns.
  constexpr int kMaxBlocks = kMaxParameters + 2;
  std::array<double, (n + 1) * kMaxBlocks> sa{}, sb{};
  double* cur = sa.data();
  double* nxt = sb.data();
  std::array<double, n + 1> r{};
  for (int i = 0; i < n; ++i) {
    cur[i] = in.x0.empty() ? 0.0 : in.x0[static_cast<std::size_t>(i)];
    r[i] = t.c[i];  // ∂y[0]/∂x0 = C
  }
  const int blocks = ks.zu_block + 1;
  for (std::size_t k = 0; k < count; ++k) {
    const double* lag_base = padded.data() + k;  // lag j at lag_base[2 − j]
    const Lags u{lag_base[2], lag_base[1], lag_base[0]};
    const double* vb = valid.data() + k;
    if (k > 0) {
      advance_states(t, ks, cur, nxt, u, vb);
      if (ks.dx0) advance_initial_state_row(t, r);
      std::swap(cur, nxt);
      if ((k & 15U) == 0) {  // decaying states would reach subnormal numbers (~100× slower)
        for (int i = 0; i < blocks * n; ++i) cur[i] = std::abs(cur[i]) < 1e-200 ? 0.0 : cur[i];
        for (int i = 0; i < n; ++i) r[i] = std::abs(r[i]) < 1e-200 ? 0.0 : r[i];
      }
    }
    double y = in.y0 + t.h[0] * u.l0 + t.h[1] * u.l1 + t.h[2] * u.l2;
    for (int i = 0; i < n; ++i) y += t.c[i] * cur[i];
    out[k] = y;
    if (jac != nullptr) jacobian_row(t, ks, cur, r, u, vb, jac + k * ks.cols);
  }
  for (std::size_t k = 0; k < count; ++k)
    if (!std::isfinite(out[k])) return false;
  return true;
}

}  // namespace

Realization realize(const lti::ProcessStructure& structure, std::span<const double> values, bool derivatives) {
  const Indices ix = indices(structure);
  const std::size_t count = values.size();
  if (count > static_cast<std::size_t>(kMaxParameters)) throw InvalidArgument("ident: too many process parameters");
  Realization r;
  if (!derivatives) {
    std::vector<double> v(values.begin(), values.end());
    realize_t<double>(structure, ix, v, r.a, r.b, r.c, r.d);
    return r;
  }
  std::vector<Jet> v(count);
  for (std::size_t i = 0; i < count; ++i) v[i] = Jet(values[i], static_cast<int>(i));
  Mat<Jet> a, b, c, d;
  realize_t<Jet>(structure, ix, v, a, b, c, d);
  auto value = [](const Mat<Jet>& m) {
    Eigen::MatrixXd out(m.rows(), m.cols());
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index j = 0; j < m.cols(); ++j) out(i, j) = m(i, j).a;
    return out;
  };
  auto partial = [](const Mat<Jet>& m, std::size_t k) {
    Eigen::MatrixXd out(m.rows(), m.cols());
    for (Eigen::Index i = 0; i < m.rows(); ++i)
      for (Eigen::Index j = 0; j < m.cols(); ++j) out(i, j) = m(i, j).v(static_cast<Eigen::Index>(k));
    return out;
  };
  r.a = value(a);
  r.b = value(b);
  r.c = value(c);
  r.d = value(d);
  for (std::size_t k = 0; k < count; ++k) {
    r.da.push_back(partial(a, k));
    r.db.push_back(partial(b, k));
    r.dc.push_back(partial(c, k));
    r.dd.push_back(partial(d, k));
  }
  return r;
}

Sampled sample(const lti::ProcessStructure& structure, std::span<const double> values, double sample_time_s,
               lti::Hold hold, bool derivatives) {
  const Indices ix = indices(structure);
  const Realization r = realize(structure, values, derivatives);
  Sampled s;
  s.n = r.a.rows();
  double fraction = 0.0;
  if (structure.delay) {  // Td = (d + f)T, snapped as lti::SampledModel
    const double samples = values[static_cast<std::size_t>(ix.td)] / sample_time_s;
    double whole = std::floor(samples);
    fraction = samples - whole;
    if (fraction > 1.0 - 1e-9) {
      whole += 1.0;
      fraction = 0.0;
    } else if (fraction < 1e-9) {
      fraction = 0.0;
    }
    s.delay_samples = static_cast<std::size_t>(std::max(0.0, whole));
  }
  s.fraction = fraction;
  const bool need_h = derivatives && structure.delay;
  const Piece p1 = make_piece(r, fraction * sample_time_s, derivatives, need_h);
  const Piece p2 = make_piece(r, (1.0 - fraction) * sample_time_s, derivatives, need_h);
  const double dval = r.d(0, 0);
  const PieceView v1{&p1.phi, &p1.gamma, &p1.lambda};
  const PieceView v2{&p2.phi, &p2.gamma, &p2.lambda};
  compose(v1, v2, dval, fraction, hold, s.phi, s.taps, s.h);
  s.c = r.c.row(0);
  if (!derivatives) return s;
  const std::size_t count = values.size();
  s.dphi.resize(count);
  s.dtaps.resize(count);
  s.dc.resize(count);
  s.dh.resize(count);
  for (std::size_t i = 0; i < count; ++i) {
    if (static_cast<int>(i) == ix.td) {  // ∂/∂Td = (1/T)∂/∂f: ∂X₁/∂Td = X₁′(fT), ∂X₂/∂Td = −X₂′((1−f)T)
      const Eigen::MatrixXd m_phi = -p2.phi_h;
      const Eigen::VectorXd m_gamma = -p2.gamma_h;
      const Eigen::VectorXd m_lambda = -p2.lambda_h;
      const PieceView d1{&p1.phi_h, &p1.gamma_h, &p1.lambda_h};
      const PieceView d2{&m_phi, &m_gamma, &m_lambda};
      compose_derivative(v1, d1, v2, d2, dval, 0.0, fraction, 1.0 / sample_time_s, hold, s.dphi[i], s.dtaps[i],
                         s.dh[i]);
      s.dc[i] = Eigen::RowVectorXd::Zero(s.n);
    } else {
      const PieceView d1{&p1.dphi[i], &p1.dgamma[i], &p1.dlambda[i]};
      const PieceView d2{&p2.dphi[i], &p2.dgamma[i], &p2.dlambda[i]};
      compose_derivative(v1, d1, v2, d2, dval, r.dd[i](0, 0), fraction, 0.0, hold, s.dphi[i], s.dtaps[i], s.dh[i]);
      s.dc[i] = r.dc[i].row(0);
    }
  }
  return s;
}

std::size_t jacobian_columns(const KernelInput& in) {
  return in.directions.size() + (in.d_x0 ? static_cast<std::size_t>(in.model->n) : 0) + (in.d_u0 ? 1 : 0) +
         (in.d_y0 ? 1 : 0);
}

bool simulate(const KernelInput& in, double* output, double* jacobian) {
  if (jacobian != nullptr && in.directions.size() > static_cast<std::size_t>(kMaxParameters)) {
    throw InvalidArgument("ident: too many sensitivity directions");
  }
  switch (in.model->n) {
    case 0: return run_kernel<0>(in, output, jacobian);
    case 1: return run_kernel<1>(in, output, jacobian);
    case 2: return run_kernel<2>(in, output, jacobian);
    case 3: return run_kernel<3>(in, output, jacobian);
    case 4: return run_kernel<4>(in, output, jacobian);
    default:
      throw InvalidArgument("ident: process model order " + std::to_string(in.model->n) + " exceeds 4");
  }
}

}  // namespace clearshape::ident::detail
