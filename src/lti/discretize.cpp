#include "clearshape/lti/discretize.hpp"

#include <complex>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"
#include "hold_integrals.hpp"

namespace clearshape::lti {

namespace detail {
HoldIntegrals hold_integrals(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double h) {
  const Eigen::Index n = a.rows();
  const Eigen::Index m = b.cols();
  // Augmented matrix of the first-order hold (scipy.signal.cont2discrete 'foh', lsim interp=True).
  Eigen::MatrixXd big = Eigen::MatrixXd::Zero(n + 2 * m, n + 2 * m);
  big.topLeftCorner(n, n) = a * h;
  big.block(0, n, n, m) = b * h;
  big.block(n, n + m, m, m).setIdentity();
  const Eigen::MatrixXd e = linalg::expm(big);  // Padé scaling and squaring (Higham 2005)
  return {e.topLeftCorner(n, n), e.block(0, n, n, m), e.block(0, n + m, n, m)};
}
}  // namespace detail

DiscreteStateSpace discretize(const StateSpace& model, double sample_time_s, Hold hold) {
  validate(model, false, "discretize");
  require_positive("sample_time_s", sample_time_s, "The sample time of a discretization must be > 0.");
  const auto in = detail::hold_integrals(model.a, model.b, sample_time_s);
  DiscreteStateSpace out;
  out.sample_time_s = sample_time_s;
  out.hold = hold;
  out.a = in.phi;
  out.c = model.c;
  if (hold == Hold::zoh) {
    out.b = in.gamma;  // Γ = ∫ e^(Aσ) dσ B
    out.d = model.d;
  } else {
    out.b = in.gamma - in.lambda + in.phi * in.lambda;  // scipy cont2discrete 'foh'
    out.d = model.d + model.c * in.lambda;
  }
  return out;
}

std::vector<double> simulate(const DiscreteStateSpace& model, std::span<const double> input,
                             const Eigen::VectorXd& x0) {
  if (model.b.cols() != 1 || model.c.rows() != 1 || model.a.rows() != model.a.cols() ||
      model.b.rows() != model.a.rows() || model.c.cols() != model.a.rows()) {
    throw InvalidArgument("simulate: the discrete model must be SISO with consistent dimensions.");
  }
  Eigen::VectorXd x = x0.size() == 0 ? Eigen::VectorXd::Zero(model.order()) : x0;
  if (x.size() != model.order()) {
    throw_invalid("simulate: x0 size", static_cast<double>(x0.size()), std::to_string(model.order()) + " (the model order)");
  }
  std::vector<double> y(input.size());
  Eigen::VectorXd next(x.size());
  for (std::size_t k = 0; k < input.size(); ++k) {
    y[k] = model.c.row(0).dot(x) + model.d(0, 0) * input[k];  // y[k] = C x[k] + D u[k]
    next.noalias() = model.a * x;
    next += model.b.col(0) * input[k];  // x[k+1] = A x[k] + B u[k]
    x = next;  // same size: no allocation
  }
  return y;
}

StateSpace continuous_equivalent(const DiscreteStateSpace& model) {
  const Eigen::Index n = model.a.rows();
  const Eigen::Index m = model.b.cols();
  require_positive("continuous_equivalent sample_time_s", model.sample_time_s);
  Eigen::MatrixXd aug = Eigen::MatrixXd::Identity(n + m, n + m);
  aug.topLeftCorner(n, n) = model.a;
  aug.topRightCorner(n, m) = model.b;
  const linalg::EigenDecomposition es = linalg::eigen(model.a);
  for (Eigen::Index k = 0; k < n; ++k) {
    const std::complex<double> z = es.values(k);
    if (std::abs(z.imag()) <= 1e-12 * std::abs(z) && z.real() <= 0.0) {
      throw RuntimeError("continuous_equivalent: discrete pole " + std::to_string(z.real()) +
                         " lies on the non-positive real axis; no real continuous model has this ZOH "
                         "equivalent (the sampling is too slow for that pole).");
    }
  }
  const Eigen::MatrixXd l = linalg::logm(aug) / model.sample_time_s;  // [A_c B_c; 0 0]
  StateSpace out;
  out.a = l.topLeftCorner(n, n);
  out.b = l.topRightCorner(n, m);
  out.c = model.c;
  out.d = model.d;
  return out;
}

}  // namespace clearshape::lti
