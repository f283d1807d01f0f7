#pragma once
// Continuous-time state-space model ẋ = A x + B u, y = C x + D u (single input, single output
// unless stated). The lti module builds these from transfer functions and process models.
#include <complex>
#include <span>
#include <vector>

#include <Eigen/Dense>

namespace clearshape::lti {

struct StateSpace {
  Eigen::MatrixXd a;  ///< n×n
  Eigen::MatrixXd b;  ///< n×m
  Eigen::MatrixXd c;  ///< p×n
  Eigen::MatrixXd d;  ///< p×m
  Eigen::Index order() const noexcept { return a.rows(); }
  bool is_siso() const noexcept { return b.cols() == 1 && c.rows() == 1; }
};

/// Checks dimensions (A square, B n×m, C p×n, D p×m) and finiteness; `require_siso` also
/// demands one input and one output. Throws InvalidArgument naming `what`.
void validate(const StateSpace& model, bool require_siso = true, const char* what = "state-space model");

/// Series connection u → first → second → y (SISO): A = [A1 0; B2 C1 A2], B = [B1; B2 D1],
/// C = [D2 C1, C2], D = D2 D1.
StateSpace series(const StateSpace& first, const StateSpace& second);

/// Poles: eigenvalues of A, sorted by real part then imaginary part.
std::vector<std::complex<double>> poles(const StateSpace& model);

/// H(jω) = C (jωI − A)⁻¹ B + D of a SISO model.
std::complex<double> frequency_response(const StateSpace& model, double frequency_rad_s);

/// ẋ = A x + B u of a SISO model, for ODE right-hand sides (e.g. CVODE N_Vector data).
/// `x` and `xdot` hold order() values each and must not overlap. noexcept, allocation-free.
void derivative(const StateSpace& model, std::span<const double> x, double input,
                std::span<double> xdot) noexcept;
/// y = C x + D u of a SISO model. noexcept, allocation-free.
double output(const StateSpace& model, std::span<const double> x, double input) noexcept;

}  // namespace clearshape::lti
