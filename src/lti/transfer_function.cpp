#include "clearshape/lti/transfer_function.hpp"

#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::lti {

TransferFunction::TransferFunction(Polynomial numerator, Polynomial denominator) {
  if (numerator.empty()) numerator = {0.0};
  if (denominator.empty()) throw InvalidArgument("transfer function denominator is empty; give at least one coefficient (descending powers of s).");
  for (double v : numerator) require_finite("transfer function numerator coefficient", v);
  for (double v : denominator) require_finite("transfer function denominator coefficient", v);
  numerator = trim_leading_zeros(std::move(numerator));
  denominator = trim_leading_zeros(std::move(denominator));
  if (denominator.size() == 1 && denominator[0] == 0.0) {
    throw InvalidArgument("transfer function denominator is the zero polynomial; it needs a non-zero coefficient.");
  }
  if (degree(numerator) > degree(denominator)) {
    throw InvalidArgument("transfer function is improper: numerator degree " + std::to_string(degree(numerator)) +
                          " > denominator degree " + std::to_string(degree(denominator)) +
                          "; allowed: numerator degree <= denominator degree (coefficients are in descending powers of s).");
  }
  const double lead = denominator.front();
  for (double& v : numerator) v /= lead;
  for (double& v : denominator) v /= lead;
  numerator_ = std::move(numerator);
  denominator_ = std::move(denominator);
}

TransferFunction TransferFunction::from_zeros_poles_gain(std::span<const std::complex<double>> zeros,
                                                         std::span<const std::complex<double>> poles,
                                                         double gain) {
  Polynomial num = from_roots(zeros);
  for (double& v : num) v *= gain;
  return TransferFunction(std::move(num), from_roots(poles));
}

std::vector<std::complex<double>> TransferFunction::poles() const { return roots(denominator_); }
std::vector<std::complex<double>> TransferFunction::zeros() const {
  if (numerator_.size() == 1 && numerator_[0] == 0.0) return {};
  return roots(numerator_);
}
std::vector<OscillatoryMode> TransferFunction::oscillatory_modes() const {
  const auto p = poles();
  return lti::oscillatory_modes(p);
}

double TransferFunction::dc_gain() const noexcept {
  return numerator_.back() / denominator_.back();  // H(0) = N(0)/D(0)
}

std::complex<double> TransferFunction::frequency_response(double frequency_rad_s) const noexcept {
  const std::complex<double> s(0.0, frequency_rad_s);
  return evaluate(numerator_, s) / evaluate(denominator_, s);
}

std::vector<std::complex<double>> TransferFunction::frequency_response(std::span<const double> frequencies_rad_s) const {
  std::vector<std::complex<double>> h;
  h.reserve(frequencies_rad_s.size());
  for (double w : frequencies_rad_s) h.push_back(frequency_response(w));
  return h;
}

StateSpace TransferFunction::controllable_canonical() const {
  const auto n = static_cast<Eigen::Index>(denominator_.size()) - 1;
  // Numerator padded to the denominator's length: b0 sⁿ + … + bn.
  std::vector<double> b(denominator_.size(), 0.0);
  std::copy(numerator_.begin(), numerator_.end(), b.end() - static_cast<std::ptrdiff_t>(numerator_.size()));
  StateSpace ss;
  ss.a = Eigen::MatrixXd::Zero(n, n);
  ss.b = Eigen::MatrixXd::Zero(n, 1);
  ss.c = Eigen::MatrixXd::Zero(1, n);
  ss.d = Eigen::MatrixXd::Constant(1, 1, b[0]);
  for (Eigen::Index j = 0; j < n; ++j) {
    const double aj = denominator_[static_cast<std::size_t>(j + 1)];
    ss.a(0, j) = -aj;                                          // first row: −a1 … −an
    ss.c(0, j) = b[static_cast<std::size_t>(j + 1)] - b[0] * aj;  // C = b_tail − b0·a_tail
  }
  for (Eigen::Index i = 1; i < n; ++i) ss.a(i, i - 1) = 1.0;
  if (n > 0) ss.b(0, 0) = 1.0;
  return ss;
}

StateSpace TransferFunction::state_space() const { return balance(controllable_canonical()); }

StateSpace balance(const StateSpace& model) {
  validate(model, true, "balance");
  StateSpace out = model;
  const Eigen::Index n = out.order();
  // Osborne iteration with radix-2 factors (as LAPACK dgebal / MATLAB ssbal): scale state i by
  // f so that the off-diagonal row norm (incl. B) and column norm (incl. C) become comparable.
  constexpr double kRadix = 2.0;
  bool changed = true;
  for (int sweep = 0; changed && sweep < 100; ++sweep) {
    changed = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      double row = std::abs(out.b(i, 0)) - std::abs(out.a(i, i));
      double col = std::abs(out.c(0, i)) - std::abs(out.a(i, i));
      row += out.a.row(i).cwiseAbs().sum();
      col += out.a.col(i).cwiseAbs().sum();
      if (row == 0.0 || col == 0.0) continue;
      double f = 1.0;
      const double sum = row + col;
      double r = row;
      double c = col;
      while (c < r / kRadix) { c *= kRadix; r /= kRadix; f *= kRadix; }
      while (c >= r * kRadix) { c /= kRadix; r *= kRadix; f /= kRadix; }
      if (c + r < 0.95 * sum) {
        changed = true;
        // x_i' = x_i / f: row i of [A B] divided by f, column i of [A; C] multiplied by f.
        out.a.row(i) /= f;
        out.b.row(i) /= f;
        out.a.col(i) *= f;
        out.c.col(i) *= f;
      }
    }
  }
  return out;
}

}  // namespace clearshape::lti
