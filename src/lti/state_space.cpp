#include "clearshape/lti/state_space.hpp"

#include <algorithm>
#include <string>


#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"

namespace clearshape::lti {

namespace {
void require_shape(const char* what, const char* matrix, const Eigen::MatrixXd& m, Eigen::Index rows,
                   Eigen::Index cols) {
  if (m.rows() != rows || m.cols() != cols) {
    throw InvalidArgument(std::string(what) + ": matrix " + matrix + " is " + std::to_string(m.rows()) +
                          "x" + std::to_string(m.cols()) + ", expected " + std::to_string(rows) + "x" +
                          std::to_string(cols) + ". Give A n×n, B n×m, C p×n, D p×m.");
  }
  if (!m.allFinite()) {
    throw InvalidArgument(std::string(what) + ": matrix " + matrix +
                          " has a NaN or infinite entry; all entries must be finite.");
  }
}

bool pole_less(const std::complex<double>& x, const std::complex<double>& y) {
  if (x.real() != y.real()) return x.real() < y.real();
  return x.imag() < y.imag();
}
}  // namespace

void validate(const StateSpace& model, bool require_siso, const char* what) {
  const Eigen::Index n = model.a.rows();
  const Eigen::Index m = model.b.cols();
  const Eigen::Index p = model.c.rows();
  require_shape(what, "A", model.a, n, n);
  require_shape(what, "B", model.b, n, m);
  require_shape(what, "C", model.c, p, n);
  require_shape(what, "D", model.d, p, m);
  if (require_siso && (m != 1 || p != 1)) {
    throw InvalidArgument(std::string(what) + " has " + std::to_string(m) + " input(s) and " +
                          std::to_string(p) + " output(s); allowed: exactly 1 of each (SISO).");
  }
}

StateSpace series(const StateSpace& first, const StateSpace& second) {
  validate(first, true, "series: first model");
  validate(second, true, "series: second model");
  const Eigen::Index n1 = first.order();
  const Eigen::Index n2 = second.order();
  StateSpace out;
  out.a = Eigen::MatrixXd::Zero(n1 + n2, n1 + n2);
  out.a.topLeftCorner(n1, n1) = first.a;
  out.a.bottomLeftCorner(n2, n1) = second.b * first.c;
  out.a.bottomRightCorner(n2, n2) = second.a;
  out.b.resize(n1 + n2, 1);
  out.b.topRows(n1) = first.b;
  out.b.bottomRows(n2) = second.b * first.d;
  out.c.resize(1, n1 + n2);
  out.c.leftCols(n1) = second.d * first.c;
  out.c.rightCols(n2) = second.c;
  out.d = second.d * first.d;
  return out;
}

std::vector<std::complex<double>> poles(const StateSpace& model) {
  validate(model, false, "poles");
  std::vector<std::complex<double>> result;
  if (model.order() == 0) return result;
  const linalg::EigenDecomposition solver = linalg::eigen(model.a);
  if (!solver.converged) throw RuntimeError("poles: eigenvalue computation did not converge");
  const Eigen::VectorXcd& values = solver.values;
  result.assign(values.data(), values.data() + values.size());
  std::sort(result.begin(), result.end(), pole_less);
  return result;
}

std::complex<double> frequency_response(const StateSpace& model, double frequency_rad_s) {
  validate(model, true, "frequency_response");
  const Eigen::Index n = model.order();
  const std::complex<double> s(0.0, frequency_rad_s);
  if (n == 0) return {model.d(0, 0), 0.0};
  const Eigen::MatrixXcd m = s * Eigen::MatrixXcd::Identity(n, n) - model.a.cast<std::complex<double>>();
  const Eigen::VectorXcd x = m.partialPivLu().solve(model.b.col(0).cast<std::complex<double>>());
  return (model.c.row(0).cast<std::complex<double>>() * x)(0) + model.d(0, 0);
}

void derivative(const StateSpace& model, std::span<const double> x, double input,
                std::span<double> xdot) noexcept {
  const Eigen::Index n = model.order();
  const Eigen::Map<const Eigen::VectorXd> xs(x.data(), n);
  Eigen::Map<Eigen::VectorXd> dx(xdot.data(), n);
  dx.noalias() = model.a * xs;  // ẋ = A x + B u
  dx += model.b.col(0) * input;
}

double output(const StateSpace& model, std::span<const double> x, double input) noexcept {
  const Eigen::Map<const Eigen::VectorXd> xs(x.data(), model.order());
  return model.c.row(0).dot(xs) + model.d(0, 0) * input;  // y = C x + D u
}

}  // namespace clearshape::lti
