#include "clearshape/lti/polynomial.hpp"

#include <algorithm>

#include <Eigen/Dense>
#include <unsupported/Eigen/Polynomials>

#include "clearshape/core/error.hpp"

namespace clearshape::lti {

Polynomial trim_leading_zeros(Polynomial p) {
  auto first = std::find_if(p.begin(), p.end(), [](double v) { return v != 0.0; });
  if (first == p.end()) return Polynomial{0.0};
  p.erase(p.begin(), first);
  return p;
}

int degree(const Polynomial& p) noexcept {
  auto first = std::find_if(p.begin(), p.end(), [](double v) { return v != 0.0; });
  if (first == p.end()) return 0;
  return static_cast<int>(p.end() - first) - 1;
}

Polynomial multiply(const Polynomial& p, const Polynomial& q) {
  if (p.empty() || q.empty()) return {};
  Polynomial r(p.size() + q.size() - 1, 0.0);
  for (std::size_t i = 0; i < p.size(); ++i)
    for (std::size_t j = 0; j < q.size(); ++j) r[i + j] += p[i] * q[j];
  return r;
}

std::complex<double> evaluate(const Polynomial& p, std::complex<double> s) noexcept {
  std::complex<double> value = 0.0;
  for (double coefficient : p) value = value * s + coefficient;  // Horner
  return value;
}

std::vector<std::complex<double>> roots(const Polynomial& p) {
  const Polynomial t = trim_leading_zeros(p);
  std::vector<std::complex<double>> result;
  if (t.size() < 2) return result;
  for (double v : t) require_finite("polynomial coefficient", v);
  // Eigen wants ascending coefficients.
  Eigen::VectorXd ascending(static_cast<Eigen::Index>(t.size()));
  for (std::size_t i = 0; i < t.size(); ++i) ascending(static_cast<Eigen::Index>(i)) = t[t.size() - 1 - i];
  Eigen::PolynomialSolver<double, Eigen::Dynamic> solver(ascending);
  const auto& r = solver.roots();
  result.assign(r.data(), r.data() + r.size());
  std::sort(result.begin(), result.end(), [](const auto& x, const auto& y) {
    if (x.real() != y.real()) return x.real() < y.real();
    return x.imag() < y.imag();
  });
  return result;
}

Polynomial from_roots(std::span<const std::complex<double>> roots_in) {
  std::vector<std::complex<double>> c{1.0};
  for (const auto& r : roots_in) {
    std::vector<std::complex<double>> next(c.size() + 1, 0.0);
    for (std::size_t i = 0; i < c.size(); ++i) {
      next[i] += c[i];
      next[i + 1] -= c[i] * r;
    }
    c.swap(next);
  }
  Polynomial p(c.size());
  std::transform(c.begin(), c.end(), p.begin(), [](const auto& v) { return v.real(); });
  return p;
}

}  // namespace clearshape::lti
