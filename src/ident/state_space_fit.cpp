#include "clearshape/ident/state_space_fit.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <limits>
#include <optional>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"
#include "clearshape/lti/polynomial.hpp"
#include "clearshape/metrics/fit.hpp"
#include "modal.hpp"

namespace clearshape::ident {

namespace {

// Characteristic polynomial det(sI − M) from the eigenvalues.
lti::Polynomial characteristic(const Eigen::MatrixXd& m) {
  const Eigen::VectorXcd values = linalg::eigen(m).values;
  std::vector<std::complex<double>> r(values.data(), values.data() + values.size());
  return lti::from_roots(r);
}

// G(s) = C(sI − A)⁻¹B + D = [det(sI − A + BC) + (D − 1) det(sI − A)] / det(sI − A), since
// det(sI − A + BC) = det(sI − A)(1 + C(sI − A)⁻¹B) (matrix determinant lemma).
lti::TransferFunction to_transfer_function(const lti::StateSpace& s) {
  const lti::Polynomial den = characteristic(s.a);
  const lti::Polynomial p_abc = characteristic(s.a - s.b * s.c);
  const double d = s.d(0, 0);
  lti::Polynomial num(den.size());
  for (std::size_t i = 0; i < den.size(); ++i) num[i] = p_abc[i] + (d - 1.0) * den[i];
  num[0] = d;  // the leading coefficients cancel exactly unless D ≠ 0
  return lti::TransferFunction(num, den);
}

// One start: the subspace model at horizon `block_rows` in real modal form, and its simulation
// cost ½ Σ e² (infinite when the simulation diverges).
struct ModalStart {
  detail::ModalModel model;
  Eigen::MatrixXd covariance;
  double cost = std::numeric_limits<double>::infinity();
};

ModalStart subspace_start(const Experiment& experiment, std::size_t order, SubspaceOptions so, std::size_t block_rows) {
  so.block_rows = block_rows;
  const SubspaceModel sub = n4sid(experiment, order, so);
  ModalStart s;
  s.model = detail::to_modal(sub.model.a, sub.model.b.col(0), sub.model.c.row(0), sub.model.d(0, 0), sub.initial_state, true);
  std::vector<double> y(experiment.size());
  if (detail::simulate(s.model, experiment.input, y.size(), y.data(), nullptr)) {
    double sse = 0.0;
    for (std::size_t k = 0; k < y.size(); ++k) sse += (y[k] - experiment.output[k]) * (y[k] - experiment.output[k]);
    if (std::isfinite(sse)) s.cost = 0.5 * sse;
  }
  return s;
}

// The horizons to start from: the given one, else max(2n, 10) and its doublings while the record
// holds them (N ≥ 2i + 2n + 10), at most 4.
std::vector<std::size_t> start_horizons(std::size_t samples, std::size_t order, const SubspaceOptions& so) {
  if (so.block_rows > 0) return {so.block_rows};
  std::vector<std::size_t> h{std::max<std::size_t>(2 * order, 10)};
  while (h.size() < 4 && samples >= 2 * (2 * h.back()) + 2 * order + 10) h.push_back(2 * h.back());
  return h;
}

// The output-error estimate is the GLOBAL minimiser of the simulation error; (JᵀJ)⁻¹σ² is its
// covariance only there (Ljung 1999, System Identification, §9.3). A short subspace horizon
// (10 samples against a 50-sample period) can start Levenberg–Marquardt outside a lightly damped
// mode's narrow basin: over seeded 10 %-noise records 30 % ended in a local minimum and the 1σ
// covered the truth in 41–50 % of them. Hence subspace starts from several horizons, ranked by
// their simulation error; the best is refined (as the process fit ranks its candidates).
ModalStart best_start(const Experiment& experiment, std::size_t order, const SubspaceOptions& so,
                      const StateSpaceFitOptions& options) {
  std::optional<ModalStart> best;
  std::optional<RuntimeError> first_error;
  for (std::size_t h : start_horizons(experiment.size(), order, so)) {
    try {
      ModalStart s = subspace_start(experiment, order, so, h);
      if (!best || s.cost < best->cost) best = std::move(s);
    } catch (const RuntimeError& e) {  // a rank-deficient subspace result at this horizon
      if (!first_error) first_error = e;
    }
  }
  if (!best) throw *first_error;
  const std::vector<bool> free = detail::free_mask(best->model, true, so.estimate_initial_state, options.feedthrough, false);
  if (!options.refine) {
    best->covariance = detail::covariance_at(best->model, experiment.input, experiment.output, free);
    return std::move(*best);
  }
  detail::ModalFit fit = detail::refine(best->model, experiment.input, experiment.output, free, options.max_iterations);
  return ModalStart{std::move(fit.model), std::move(fit.covariance), fit.cost};
}

}  // namespace

StateSpaceEstimate estimate_state_space(const Experiment& experiment, std::size_t order,
                                        const StateSpaceFitOptions& options) {
  validate(experiment);
  const bool with_x0 = options.initial_state != InitialState::zero;
  SubspaceOptions so = options.subspace;
  so.feedthrough = options.feedthrough;
  so.estimate_initial_state = with_x0;
  const ModalStart start = best_start(experiment, order, so, options);
  const detail::ModalModel& modal = start.model;
  const Eigen::MatrixXd& covariance = start.covariance;
  const std::vector<bool> free = detail::free_mask(modal, true, with_x0, options.feedthrough, false);
  const std::size_t n = experiment.size();
  StateSpaceEstimate est;
  est.refined = options.refine;
  est.discrete = detail::to_state_space(modal, experiment.sample_time_s);
  est.initial_state = detail::initial_state(modal);
  std::vector<double> y(n);
  if (!detail::simulate(modal, experiment.input, n, y.data(), nullptr)) {
    throw RuntimeError("estimate_state_space: the identified model diverges on experiment \"" + experiment.name +
                       "\"; try a lower order.");
  }
  est.simulated = UniformSeries{0.0, experiment.sample_time_s, y};
  est.fit_percent = metrics::fit_percent(experiment.output, y);
  est.rmse = metrics::rmse(experiment.output, y);
  est.parameters = static_cast<std::size_t>(std::count(free.begin(), free.end(), true));
  est.loss = est.rmse * est.rmse;
  const double pn = static_cast<double>(est.parameters) / static_cast<double>(n);
  est.fpe = est.loss * (1.0 + pn) / (1.0 - pn);  // Akaike FPE
  est.aic = static_cast<double>(n) * std::log(est.loss) + 2.0 * static_cast<double>(est.parameters);
  try {
    est.continuous = lti::continuous_equivalent(est.discrete);
    est.transfer_function = to_transfer_function(*est.continuous);
  } catch (const RuntimeError&) {
    // A pole on the negative real axis: no continuous equivalent; the discrete model stands.
  }
  for (std::size_t b = 0; b < modal.blocks.size(); ++b) {
    if (!modal.blocks[b].complex) continue;
    est.modes.push_back(
        detail::mode_estimate(modal, b, covariance, experiment.sample_time_s, experiment.input, n));
  }
  std::stable_sort(est.modes.begin(), est.modes.end(),
                   [](const ModeEstimate& a, const ModeEstimate& b) { return a.rms_contribution > b.rms_contribution; });
  return est;
}

ExperimentFit compare(const StateSpaceEstimate& estimate, const Experiment& experiment) {
  validate(experiment);
  lti::DiscreteStateSpace m = estimate.discrete;
  if (std::abs(m.sample_time_s - experiment.sample_time_s) > 1e-9 * experiment.sample_time_s) {
    throw_invalid("compare: experiment sample_time_s", experiment.sample_time_s,
                  std::to_string(m.sample_time_s) + " (the model's sample time)",
                  "Validate on data recorded at the estimation sample time.");
  }
  const std::vector<double> y = lti::simulate(m, experiment.input);
  ExperimentFit fit;
  fit.name = experiment.name;
  fit.fit_percent = fit.fit_percent_zero_ic = metrics::fit_percent(experiment.output, y);
  // Initial state fitted by least squares: y − y_zero ≈ [C; CA; CA²; …] x0 (MATLAB compare default).
  const Eigen::Index n = m.order();
  const auto rows = static_cast<Eigen::Index>(y.size());
  Eigen::MatrixXd obs(rows, n);
  Eigen::RowVectorXd cak = m.c.row(0);
  Eigen::VectorXd r(rows);
  for (Eigen::Index k = 0; k < rows; ++k) {
    obs.row(k) = cak;
    cak = cak * m.a;
    r(k) = experiment.output[static_cast<std::size_t>(k)] - y[static_cast<std::size_t>(k)];
  }
  const Eigen::VectorXd x0 = obs.colPivHouseholderQr().solve(r);
  const Eigen::VectorXd free_part = obs * x0;
  std::vector<double> y_est(y);
  for (Eigen::Index k = 0; k < rows; ++k) y_est[static_cast<std::size_t>(k)] += free_part(k);
  fit.fit_percent_estimated_ic = metrics::fit_percent(experiment.output, y_est);
  fit.rmse = metrics::rmse(experiment.output, y);
  fit.initial_state = Eigen::VectorXd::Zero(m.order());
  fit.simulated = UniformSeries{0.0, experiment.sample_time_s, y};
  return fit;
}

}  // namespace clearshape::ident
