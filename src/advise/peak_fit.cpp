#include "peak_fit.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include <Eigen/Dense>

namespace clearshape::advise::detail {

namespace {

// ln of the model's power at each bin; x = (a, f0, ln ζ) per line.
Eigen::VectorXd log_model(const std::vector<double>& f, const Eigen::VectorXd& x, bool coherent) {
  const Eigen::Index lines = x.size() / 3;
  Eigen::VectorXd out(static_cast<Eigen::Index>(f.size()));
  for (std::size_t i = 0; i < f.size(); ++i) {
    std::complex<double> sum{0.0, 0.0};
    double power = 0.0;
    for (Eigen::Index l = 0; l < lines; ++l) {
      const double a = x(3 * l), f0 = x(3 * l + 1), z = std::exp(x(3 * l + 2));
      const std::complex<double> d(f0 * f0 - f[i] * f[i], 2.0 * z * f0 * f[i]);
      if (coherent) {
        sum += a / d;
      } else {
        power += a * a / std::norm(d);
      }
    }
    const double p = f[i] * f[i] * (coherent ? std::norm(sum) : power);
    out(static_cast<Eigen::Index>(i)) = std::log(std::max(p, 1e-300));
  }
  return out;
}

Eigen::MatrixXd jacobian(const std::vector<double>& f, const Eigen::VectorXd& x, bool coherent, const Eigen::VectorXd& at) {
  Eigen::MatrixXd j(at.size(), x.size());
  for (Eigen::Index c = 0; c < x.size(); ++c) {
    Eigen::VectorXd xp = x;
    // Relative step: the same fit whatever the units of frequency and power.
    const double h = 1e-6 * (x(c) != 0.0 ? std::abs(x(c)) : 1.0);
    xp(c) += h;
    j.col(c) = (log_model(f, xp, coherent) - at) / h;
  }
  return j;
}

}  // namespace

double line_power(const LineFit& line, double f) noexcept {
  const std::complex<double> d(line.frequency_hz * line.frequency_hz - f * f, 2.0 * line.damping_ratio * line.frequency_hz * f);
  return line.residue * line.residue * f * f / std::norm(d);
}

LinesFit fit_lines(std::span<const double> frequency_hz, std::span<const double> power, std::size_t first, std::size_t last,
                   const std::vector<LineStart>& starts, bool coherent, const std::vector<double>& signs, double correlation) {
  // The fit runs on frequency / the first line's start and power / the band's maximum, so it does
  // the same steps whatever the units of time and of the signal (the design is scale-free).
  const double f_ref = starts.empty() ? 1.0 : starts.front().frequency_hz;
  double p_ref = 0.0;
  for (std::size_t k = first; k <= last && k < power.size(); ++k) p_ref = std::max(p_ref, power[k]);
  std::vector<double> f;
  Eigen::VectorXd log_p(static_cast<Eigen::Index>(last - first + 1));
  Eigen::Index used = 0;
  for (std::size_t k = first; k <= last && k < power.size(); ++k) {
    if (frequency_hz[k] > 0.0 && power[k] > 0.0) {
      f.push_back(frequency_hz[k] / f_ref);
      log_p(used++) = std::log(power[k] / p_ref);
    }
  }
  log_p.conservativeResize(used);
  LinesFit result;
  result.lines.resize(starts.size());
  for (std::size_t l = 0; l < starts.size(); ++l) {
    result.lines[l].frequency_hz = starts[l].frequency_hz;
    result.lines[l].damping_ratio = starts[l].damping_ratio;
  }
  const auto p = static_cast<Eigen::Index>(3 * starts.size());
  if (f.size() < 3 * starts.size() + 3 || !(f_ref > 0.0)) return result;
  // Start: each line's residue puts its peak, P = a²/(2ζ f0)², on the measured power there.
  Eigen::VectorXd x(p);
  for (std::size_t l = 0; l < starts.size(); ++l) {
    const auto nearest = std::min_element(f.begin(), f.end(), [&](double a, double b) {
      return std::abs(a - starts[l].frequency_hz / f_ref) < std::abs(b - starts[l].frequency_hz / f_ref);
    });
    const double peak = std::exp(log_p(nearest - f.begin()));
    const double z = starts[l].damping_ratio, f0 = starts[l].frequency_hz / f_ref;
    const double sign = coherent && l < signs.size() ? signs[l] : 1.0;
    const auto b = static_cast<Eigen::Index>(3 * l);
    x(b) = sign * std::sqrt(peak) * 2.0 * z * f0;
    x(b + 1) = f0;
    x(b + 2) = std::log(z);
  }
  Eigen::VectorXd model = log_model(f, x, coherent);
  Eigen::VectorXd r = model - log_p;
  Eigen::MatrixXd j = jacobian(f, x, coherent, model);
  double cost = r.squaredNorm();
  double lambda = 1e-3;
  for (int it = 0; it < 300; ++it) {
    const Eigen::MatrixXd h = j.transpose() * j;
    Eigen::MatrixXd a = h;
    a.diagonal() += lambda * h.diagonal() + Eigen::VectorXd::Constant(p, 1e-12 * h.diagonal().maxCoeff());
    const Eigen::VectorXd step = a.ldlt().solve(-(j.transpose() * r));
    Eigen::VectorXd trial = x + step;
    bool valid = step.allFinite();
    for (Eigen::Index l = 0; l < p / 3; ++l) {
      trial(3 * l + 2) = std::clamp(trial(3 * l + 2), std::log(kMinLineDamping), std::log(kMaxLineDamping));
      valid = valid && trial(3 * l + 1) > 0.0;
    }
    const Eigen::VectorXd trial_model = valid ? log_model(f, trial, coherent) : model;
    const double next_cost = valid ? (trial_model - log_p).squaredNorm() : cost;
    if (valid && next_cost < cost) {
      const bool small = cost - next_cost <= 1e-12 * cost;
      x = trial;
      model = trial_model;
      r = model - log_p;
      j = jacobian(f, x, coherent, model);
      cost = next_cost;
      lambda = std::max(lambda / 10.0, 1e-12);
      if (small) break;
    } else {
      lambda *= 10.0;
      if (lambda > 1e12) break;
    }
  }
  const auto n = static_cast<double>(f.size());
  const Eigen::MatrixXd cov =
      (j.transpose() * j).inverse() * (cost / std::max(1.0, n - static_cast<double>(p))) * std::max(1.0, correlation);
  result.cost = cost;
  result.converged = cov.allFinite();
  for (std::size_t l = 0; l < starts.size(); ++l) {
    const auto b = static_cast<Eigen::Index>(3 * l);
    LineFit& line = result.lines[l];
    // Back to the caller's units: P = a² f² / |f0² − f² + 2jζ f0 f|² scales a by f_ref·√p_ref.
    line.residue = x(b) * f_ref * std::sqrt(p_ref);
    line.frequency_hz = x(b + 1) * f_ref;
    line.damping_ratio = std::exp(x(b + 2));
    line.frequency_var = cov(b + 1, b + 1) * f_ref * f_ref;
    line.log_damping_var = cov(b + 2, b + 2);
    line.converged = result.converged && line.frequency_hz > 0.0 && line.frequency_var >= 0.0;
    result.converged = result.converged && line.converged;
  }
  return result;
}

}  // namespace clearshape::advise::detail
