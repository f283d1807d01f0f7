#pragma once
// Real polynomials in s. Coefficients are stored in DESCENDING powers, as in SciPy and MATLAB:
// {a0, a1, …, an} means a0·sⁿ + a1·sⁿ⁻¹ + … + an.
#include <complex>
#include <span>
#include <vector>

namespace clearshape::lti {

using Polynomial = std::vector<double>;

/// Removes leading (highest-power) coefficients that are exactly zero; keeps at least one.
Polynomial trim_leading_zeros(Polynomial p);
/// Degree after trimming (0 for a constant, including the zero polynomial).
int degree(const Polynomial& p) noexcept;
/// Product of two polynomials (discrete convolution of the coefficient lists).
Polynomial multiply(const Polynomial& p, const Polynomial& q);
/// p(s) by Horner's rule.
std::complex<double> evaluate(const Polynomial& p, std::complex<double> s) noexcept;
/// Roots via the eigenvalues of the balanced companion matrix (Eigen PolynomialSolver),
/// sorted by real part then imaginary part. A constant has no roots.
std::vector<std::complex<double>> roots(const Polynomial& p);
/// Monic polynomial with the given roots; complex roots must come in conjugate pairs (the
/// imaginary part of the expanded coefficients, at rounding level, is dropped).
Polynomial from_roots(std::span<const std::complex<double>> roots);

}  // namespace clearshape::lti
