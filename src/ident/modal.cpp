#include "modal.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <numbers>
#include <string>

#include <ceres/ceres.h>

#include "clearshape/core/linalg.hpp"
#include "clearshape/core/error.hpp"
#include "covariance.hpp"

namespace clearshape::ident::detail {

namespace {

std::size_t block_parameters(const ModalBlock& b) { return b.complex ? 6 : 3; }

inline double flush(double v) noexcept { return std::abs(v) < 1e-250 ? 0.0 : v; }

// J = [0 −1; 1 0] commutes with r·R(θ); S = αI + βJ.
void s_times(double alpha, double beta, const double v[2], double out[2]) {
  out[0] = alpha * v[0] - beta * v[1];
  out[1] = beta * v[0] + alpha * v[1];
}

class ModalCost final : public ceres::CostFunction {
 public:
  ModalCost(const ModalModel& start, std::span<const double> input, std::span<const double> output,
            std::vector<int> free_index)
      : model_(start), input_(input), output_(output), free_index_(std::move(free_index)),
        full_(pack(start)), y_(output.size()), jac_() {
    set_num_residuals(static_cast<int>(output.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(free_index_.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    for (std::size_t i = 0; i < free_index_.size(); ++i) full_[static_cast<std::size_t>(free_index_[i])] = parameters[0][i];
    unpack(full_, model_);
    const std::size_t n = output_.size();
    const bool want = jacobians != nullptr && jacobians[0] != nullptr;
    if (want) jac_.resize(n * full_.size());
    if (!simulate(model_, input_, n, y_.data(), want ? jac_.data() : nullptr)) return false;
    for (std::size_t k = 0; k < n; ++k) residuals[k] = y_[k] - output_[k];
    if (want) {
      const std::size_t m = free_index_.size();
      for (std::size_t k = 0; k < n; ++k)
        for (std::size_t i = 0; i < m; ++i)
          jacobians[0][k * m + i] = jac_[static_cast<std::size_t>(free_index_[i]) * n + k];
    }
    return true;
  }

 private:
  mutable ModalModel model_;
  std::span<const double> input_;
  std::span<const double> output_;
  std::vector<int> free_index_;
  mutable std::vector<double> full_;
  mutable std::vector<double> y_;
  mutable std::vector<double> jac_;
};

std::vector<int> free_indices(const std::vector<bool>& free) {
  std::vector<int> idx;
  for (std::size_t i = 0; i < free.size(); ++i)
    if (free[i]) idx.push_back(static_cast<int>(i));
  return idx;
}

Eigen::MatrixXd scaled_covariance(ceres::Problem& problem, double* x, std::size_t free_count, double cost,
                                  std::size_t samples, const std::vector<int>& idx, std::size_t total) {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(total), static_cast<Eigen::Index>(total));
  const double sigma2 = samples > free_count ? 2.0 * cost / static_cast<double>(samples - free_count)
                                             : std::numeric_limits<double>::quiet_NaN();
  const Eigen::MatrixXd c = parameter_covariance(problem, {x}, sigma2, free_count);
  for (std::size_t i = 0; i < free_count; ++i)
    for (std::size_t j = 0; j < free_count; ++j)
      out(idx[i], idx[j]) = c(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
  return out;
}

}  // namespace

std::size_t parameter_count(const ModalModel& model) {
  std::size_t p = 2;
  for (const auto& b : model.blocks) p += block_parameters(b);
  return p;
}

std::size_t block_offset(const ModalModel& model, std::size_t block) {
  std::size_t p = 0;
  for (std::size_t i = 0; i < block; ++i) p += block_parameters(model.blocks[i]);
  return p;
}

std::vector<double> pack(const ModalModel& model) {
  std::vector<double> v;
  for (const auto& b : model.blocks) {
    if (b.complex) {
      v.insert(v.end(), {b.pole0, b.pole1, b.c[0], b.c[1], b.x0[0], b.x0[1]});
    } else {
      v.insert(v.end(), {b.pole0, b.c[0], b.x0[0]});
    }
  }
  v.push_back(model.d);
  v.push_back(model.offset);
  return v;
}

void unpack(std::span<const double> v, ModalModel& model) {
  std::size_t p = 0;
  for (auto& b : model.blocks) {
    if (b.complex) {
      b.pole0 = v[p];
      b.pole1 = v[p + 1];
      b.c[0] = v[p + 2];
      b.c[1] = v[p + 3];
      b.x0[0] = v[p + 4];
      b.x0[1] = v[p + 5];
      p += 6;
    } else {
      b.pole0 = v[p];
      b.c[0] = v[p + 1];
      b.x0[0] = v[p + 2];
      p += 3;
    }
  }
  model.d = v[p];
  model.offset = v[p + 1];
}

bool simulate(const ModalModel& model, std::span<const double> input, std::size_t count, double* output,
              double* jacobian) {
  const bool with_input = model.has_input && !input.empty();
  for (std::size_t k = 0; k < count; ++k) {
    output[k] = model.offset + (with_input ? model.d * input[k] : 0.0);
  }
  if (jacobian != nullptr) {
    const std::size_t total = parameter_count(model);
    std::fill(jacobian, jacobian + total * count, 0.0);
    const std::size_t pd = total - 2;
    for (std::size_t k = 0; k < count; ++k) {
      jacobian[pd * count + k] = with_input ? input[k] : 0.0;
      jacobian[(pd + 1) * count + k] = 1.0;
    }
  }
  std::size_t p = 0;
  for (const auto& b : model.blocks) {
    if (b.complex) {
      const double r = std::exp(b.pole0);
      const double a00 = r * std::cos(b.pole1), a10 = r * std::sin(b.pole1);  // r·R(θ) = [a00 −a10; a10 a00]
      double x[2] = {b.x0[0], b.x0[1]};
      double sl[2] = {0.0, 0.0}, st[2] = {0.0, 0.0};
      double w[4] = {1.0, 0.0, 0.0, 1.0};  // Aᵏ, row-major
      for (std::size_t k = 0; k < count; ++k) {
        const double y = b.c[0] * x[0] + b.c[1] * x[1];
        output[k] += y;
        if (jacobian != nullptr) {
          jacobian[p * count + k] = b.c[0] * sl[0] + b.c[1] * sl[1];        // ∂/∂ ln r
          jacobian[(p + 1) * count + k] = b.c[0] * st[0] + b.c[1] * st[1];  // ∂/∂θ
          jacobian[(p + 2) * count + k] = x[0];
          jacobian[(p + 3) * count + k] = x[1];
          jacobian[(p + 4) * count + k] = b.c[0] * w[0] + b.c[1] * w[2];  // c Aᵏ
          jacobian[(p + 5) * count + k] = b.c[0] * w[1] + b.c[1] * w[3];
        }
        const double u = with_input ? input[k] : 0.0;
        const double ax0 = a00 * x[0] - a10 * x[1], ax1 = a10 * x[0] + a00 * x[1];
        if (jacobian != nullptr) {
          // ∂A/∂ln r = A, ∂A/∂θ = A J with J x = (−x1, x0).
          const double nsl0 = a00 * sl[0] - a10 * sl[1] + ax0, nsl1 = a10 * sl[0] + a00 * sl[1] + ax1;
          const double ajx0 = -a00 * x[1] - a10 * x[0], ajx1 = -a10 * x[1] + a00 * x[0];
          const double nst0 = a00 * st[0] - a10 * st[1] + ajx0, nst1 = a10 * st[0] + a00 * st[1] + ajx1;
          sl[0] = nsl0;
          sl[1] = nsl1;
          st[0] = nst0;
          st[1] = nst1;
          const double w0 = a00 * w[0] - a10 * w[2], w1 = a00 * w[1] - a10 * w[3];
          const double w2 = a10 * w[0] + a00 * w[2], w3 = a10 * w[1] + a00 * w[3];
          w[0] = flush(w0);  // decaying powers would reach slow subnormal numbers
          w[1] = flush(w1);
          w[2] = flush(w2);
          w[3] = flush(w3);
        }
        x[0] = flush(ax0);
        x[1] = flush(ax1 + u);  // b = [0 1]ᵀ
      }
      p += 6;
    } else {
      const double a = b.pole0;
      double x = b.x0[0], s = 0.0, w = 1.0;
      for (std::size_t k = 0; k < count; ++k) {
        output[k] += b.c[0] * x;
        if (jacobian != nullptr) {
          jacobian[p * count + k] = b.c[0] * s;
          jacobian[(p + 1) * count + k] = x;
          jacobian[(p + 2) * count + k] = b.c[0] * w;
          s = flush(a * s + x);
          w = flush(w * a);
        }
        x = flush(a * x + (with_input ? input[k] : 0.0));
      }
      p += 3;
    }
  }
  for (std::size_t k = 0; k < count; ++k)
    if (!std::isfinite(output[k])) return false;
  return true;
}

std::vector<double> block_output(const ModalModel& model, std::size_t block, std::span<const double> input,
                                 std::size_t count) {
  ModalModel one;
  one.has_input = model.has_input;
  one.blocks.push_back(model.blocks[block]);
  std::vector<double> y(count);
  simulate(one, input, count, y.data(), nullptr);
  return y;
}

ModalModel to_modal(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::RowVectorXd& c, double d,
                    const Eigen::VectorXd& x0, bool has_input) {
  const Eigen::Index n = a.rows();
  const linalg::EigenDecomposition es = linalg::eigen(a, true);
  if (!es.converged) throw RuntimeError("modal form: the eigen-decomposition of A failed");
  Eigen::MatrixXd t(n, n);
  std::vector<ModalBlock> blocks;
  Eigen::Index col = 0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const std::complex<double> z = es.values(k);
    const double tol = 1e-10 * std::max(1.0, std::abs(z));
    if (z.imag() < -tol) continue;  // conjugate of a pair taken below
    ModalBlock blk;
    const Eigen::VectorXcd v = es.vectors.col(k);
    if (z.imag() > tol) {
      if (col + 2 > n) break;
      blk.complex = true;
      blk.pole0 = std::log(std::abs(z));
      blk.pole1 = std::arg(z);
      t.col(col) = v.real();   // A [Re v, −Im v] = [Re v, −Im v]·r R(θ)
      t.col(col + 1) = -v.imag();
      col += 2;
    } else {
      if (col + 1 > n) break;
      blk.complex = false;
      blk.pole0 = z.real();
      t.col(col) = v.real();
      col += 1;
    }
    blocks.push_back(blk);
  }
  Eigen::FullPivLU<Eigen::MatrixXd> lu(t);
  if (col != n || lu.rank() < n) {
    throw RuntimeError("modal form: A has repeated poles without a full set of eigenvectors; use a different order");
  }
  const Eigen::VectorXd bm = has_input ? Eigen::VectorXd(lu.solve(b)) : Eigen::VectorXd::Zero(n);
  const Eigen::RowVectorXd cm = c * t;
  const Eigen::VectorXd xm = x0.size() == n ? Eigen::VectorXd(lu.solve(x0)) : Eigen::VectorXd::Zero(n);
  ModalModel model;
  model.has_input = has_input;
  model.d = has_input ? d : 0.0;
  Eigen::Index s = 0;
  for (auto& blk : blocks) {
    if (blk.complex) {
      const double bb[2] = {bm(s), bm(s + 1)}, cc[2] = {cm(s), cm(s + 1)}, xx[2] = {xm(s), xm(s + 1)};
      double alpha = 0.0, beta = 0.0;
      if (has_input) {  // S [0 1]ᵀ = b  →  α = b1, β = −b0; c' = c S, x0' = S⁻¹ x0
        alpha = bb[1];
        beta = -bb[0];
      } else {  // c S = [1 0]
        const double q = cc[0] * cc[0] + cc[1] * cc[1];
        alpha = q > 0.0 ? cc[0] / q : 1.0;
        beta = q > 0.0 ? cc[1] / q : 0.0;
      }
      const double q = alpha * alpha + beta * beta;
      if (q > 0.0) {
        // c S: [α c0 + β c1, α c1 − β c0]; S⁻¹ = (αI − βJ)/q.
        blk.c[0] = alpha * cc[0] + beta * cc[1];
        blk.c[1] = alpha * cc[1] - beta * cc[0];
        s_times(alpha / q, -beta / q, xx, blk.x0);
      } else {
        blk.c[0] = 0.0;
        blk.c[1] = 0.0;
        blk.x0[0] = xx[0];
        blk.x0[1] = xx[1];
      }
      if (!has_input) {
        blk.c[0] = 1.0;
        blk.c[1] = 0.0;
      }
      s += 2;
    } else {
      const double beta = has_input ? bm(s) : 1.0 / (cm(s) != 0.0 ? cm(s) : 1.0);
      blk.c[0] = cm(s) * beta;
      blk.x0[0] = beta != 0.0 ? xm(s) / beta : 0.0;
      if (!has_input) blk.c[0] = 1.0;
      s += 1;
    }
  }
  model.blocks = std::move(blocks);
  return model;
}

lti::DiscreteStateSpace to_state_space(const ModalModel& model, double sample_time_s) {
  Eigen::Index n = 0;
  for (const auto& b : model.blocks) n += static_cast<Eigen::Index>(b.states());
  lti::DiscreteStateSpace out;
  out.a = Eigen::MatrixXd::Zero(n, n);
  out.b = Eigen::MatrixXd::Zero(n, 1);
  out.c = Eigen::MatrixXd::Zero(1, n);
  out.d = Eigen::MatrixXd::Constant(1, 1, model.d);
  out.sample_time_s = sample_time_s;
  out.hold = lti::Hold::zoh;
  Eigen::Index s = 0;
  for (const auto& b : model.blocks) {
    if (b.complex) {
      const double r = std::exp(b.pole0);
      out.a(s, s) = r * std::cos(b.pole1);
      out.a(s, s + 1) = -r * std::sin(b.pole1);
      out.a(s + 1, s) = r * std::sin(b.pole1);
      out.a(s + 1, s + 1) = r * std::cos(b.pole1);
      out.b(s + 1, 0) = model.has_input ? 1.0 : 0.0;
      out.c(0, s) = b.c[0];
      out.c(0, s + 1) = b.c[1];
      s += 2;
    } else {
      out.a(s, s) = b.pole0;
      out.b(s, 0) = model.has_input ? 1.0 : 0.0;
      out.c(0, s) = b.c[0];
      s += 1;
    }
  }
  return out;
}

Eigen::VectorXd initial_state(const ModalModel& model) {
  std::vector<double> x;
  for (const auto& b : model.blocks) {
    x.push_back(b.x0[0]);
    if (b.complex) x.push_back(b.x0[1]);
  }
  return Eigen::Map<Eigen::VectorXd>(x.data(), static_cast<Eigen::Index>(x.size()));
}

std::vector<bool> free_mask(const ModalModel& model, bool free_c, bool free_x0, bool free_d, bool free_offset) {
  std::vector<bool> f;
  for (const auto& b : model.blocks) {
    if (b.complex) {
      f.insert(f.end(), {true, true, free_c, free_c, free_x0, free_x0});
    } else {
      f.insert(f.end(), {true, free_c, free_x0});
    }
  }
  f.push_back(free_d);
  f.push_back(free_offset);
  return f;
}

ModalFit refine(const ModalModel& start, std::span<const double> input, std::span<const double> output,
                const std::vector<bool>& free, std::size_t max_iterations) {
  const std::vector<int> idx = free_indices(free);
  std::vector<double> full = pack(start);
  std::vector<double> x;
  for (int i : idx) x.push_back(full[static_cast<std::size_t>(i)]);
  ModalFit fit;
  fit.model = start;
  if (x.empty()) return fit;
  ceres::Problem::Options po;
  ceres::Problem problem(po);
  problem.AddResidualBlock(new ModalCost(start, input, output, idx), nullptr, x.data());
  // θ of each complex pair stays in (0, π): the cost is periodic in θ and even under θ → −θ
  // (with the state reflected), so an unbounded step could land on an alias of the mode.
  for (std::size_t i = 0; i < idx.size(); ++i) {
    std::size_t p = 0;
    for (const auto& b : start.blocks) {
      if (b.complex && static_cast<std::size_t>(idx[i]) == p + 1) {
        problem.SetParameterLowerBound(x.data(), static_cast<int>(i), 1e-9);
        problem.SetParameterUpperBound(x.data(), static_cast<int>(i), std::numbers::pi - 1e-9);
      }
      p += block_parameters(b);
    }
  }
  ceres::Solver::Options so;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = static_cast<int>(max_iterations);
  so.function_tolerance = 1e-13;
  so.gradient_tolerance = 1e-14;
  so.parameter_tolerance = 1e-12;
  so.logging_type = ceres::SILENT;
  so.num_threads = 1;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  for (std::size_t i = 0; i < idx.size(); ++i) full[static_cast<std::size_t>(idx[i])] = x[i];
  unpack(full, fit.model);
  fit.cost = summary.final_cost;
  fit.iterations = summary.iterations.size();
  fit.converged = summary.termination_type == ceres::CONVERGENCE;
  fit.covariance = scaled_covariance(problem, x.data(), x.size(), summary.final_cost, output.size(), idx, full.size());
  return fit;
}

Eigen::MatrixXd covariance_at(const ModalModel& model, std::span<const double> input, std::span<const double> output,
                              const std::vector<bool>& free) {
  const std::vector<int> idx = free_indices(free);
  const std::vector<double> full = pack(model);
  std::vector<double> x;
  for (int i : idx) x.push_back(full[static_cast<std::size_t>(i)]);
  if (x.empty()) return Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(full.size()), static_cast<Eigen::Index>(full.size()));
  ceres::Problem problem;
  problem.AddResidualBlock(new ModalCost(model, input, output, idx), nullptr, x.data());
  double cost = 0.0;
  problem.Evaluate(ceres::Problem::EvaluateOptions(), &cost, nullptr, nullptr, nullptr);
  return scaled_covariance(problem, x.data(), x.size(), cost, output.size(), idx, full.size());
}

ModeEstimate mode_estimate(const ModalModel& model, std::size_t block, const Eigen::MatrixXd& covariance,
                           double sample_time_s, std::span<const double> input, std::size_t count) {
  const ModalBlock& b = model.blocks[block];
  const auto p = static_cast<Eigen::Index>(block_offset(model, block));
  const double l = b.pole0, th = b.pole1, T = sample_time_s;
  const double rho = std::hypot(l, th);
  ModeEstimate m;
  m.natural_frequency_rad_s = rho / T;  // s = (ln r + iθ)/T, ωn = |s|
  m.damping_ratio = -l / rho;           // ζ = −Re s / |s|
  const Eigen::Matrix2d cov = covariance.block(p, p, 2, 2);
  const Eigen::RowVector2d g_wn(l / (rho * T), th / (rho * T));
  const Eigen::RowVector2d g_z(-th * th / (rho * rho * rho), l * th / (rho * rho * rho));
  m.natural_frequency_std_rad_s = std::sqrt(std::max(0.0, (g_wn * cov * g_wn.transpose())(0, 0)));
  m.damping_ratio_std = std::sqrt(std::max(0.0, (g_z * cov * g_z.transpose())(0, 0)));
  if (!model.has_input) {  // amplitude ‖x0‖ of r^k (x00 cos kθ − x01 sin kθ)
    m.amplitude = std::hypot(b.x0[0], b.x0[1]);
    const Eigen::Matrix2d cx = covariance.block(p + 4, p + 4, 2, 2);
    if (m.amplitude > 0.0) {
      const Eigen::RowVector2d g(b.x0[0] / m.amplitude, b.x0[1] / m.amplitude);
      m.amplitude_std = std::sqrt(std::max(0.0, (g * cx * g.transpose())(0, 0)));
    }
  } else {  // |c (e^(iθ) I − A)⁻¹ b| with b = [0 1]ᵀ, by the delta method (central differences)
    auto gain = [](double ll, double tt, double c0, double c1) {
      const std::complex<double> z = std::polar(1.0, tt);
      const double r = std::exp(ll);
      const std::complex<double> a00 = z - r * std::cos(tt), a01 = r * std::sin(tt);
      const std::complex<double> a10 = -r * std::sin(tt), a11 = z - r * std::cos(tt);
      const std::complex<double> det = a00 * a11 - a01 * a10;
      // (zI − A)⁻¹ [0 1]ᵀ = [−a01; a00]/det
      return std::abs((c0 * (-a01) + c1 * a00) / det);
    };
    const double v[4] = {l, th, b.c[0], b.c[1]};
    m.amplitude = gain(v[0], v[1], v[2], v[3]);
    Eigen::RowVector4d g;
    for (int i = 0; i < 4; ++i) {
      double hi[4] = {v[0], v[1], v[2], v[3]}, lo[4] = {v[0], v[1], v[2], v[3]};
      const double h = 1e-6 * std::max(1e-3, std::abs(v[i]));
      hi[i] += h;
      lo[i] -= h;
      g(i) = (gain(hi[0], hi[1], hi[2], hi[3]) - gain(lo[0], lo[1], lo[2], lo[3])) / (2.0 * h);
    }
    const Eigen::Matrix4d c4 = covariance.block(p, p, 4, 4);
    m.amplitude_std = std::sqrt(std::max(0.0, (g * c4 * g.transpose())(0, 0)));
  }
  if (!covariance.allFinite()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    m.natural_frequency_std_rad_s = m.damping_ratio_std = m.amplitude_std = nan;
  }
  const std::vector<double> y = block_output(model, block, input, count);
  double s = 0.0;
  for (double v : y) s += v * v;
  m.rms_contribution = count > 0 ? std::sqrt(s / static_cast<double>(count)) : 0.0;
  return m;
}

}  // namespace clearshape::ident::detail
