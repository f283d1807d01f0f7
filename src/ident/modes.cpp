#include "clearshape/ident/modes.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/linalg.hpp"
#include "clearshape/dsp/peaks.hpp"
#include "clearshape/dsp/welch.hpp"
#include "clearshape/ident/state_space_fit.hpp"
#include "clearshape/ident/subspace.hpp"
#include "clearshape/metrics/fit.hpp"
#include "decimation.hpp"
#include "modal.hpp"

namespace clearshape::ident {

double ModeEstimate::natural_frequency_hz() const noexcept {
  return natural_frequency_rad_s / (2.0 * std::numbers::pi);
}
double ModeEstimate::damped_frequency_rad_s() const noexcept {
  return damping_ratio < 1.0 ? natural_frequency_rad_s * std::sqrt(1.0 - damping_ratio * damping_ratio) : 0.0;
}
double ModeEstimate::damped_frequency_hz() const noexcept {
  return damped_frequency_rad_s() / (2.0 * std::numbers::pi);
}
double ModeEstimate::natural_frequency_std_hz() const noexcept {
  return natural_frequency_std_rad_s / (2.0 * std::numbers::pi);
}

namespace {

void check_options(const ModeOptions& options) {
  if (options.modes < 1) throw_invalid("modes", 0.0, ">= 1", "Ask for at least one mode.");
  require_in_open("max_damping_ratio", options.max_damping_ratio, 0.0, 1.0 + 1e-12,
                  "Modes with ζ >= 1 do not oscillate; keep the limit below 1.");
}

// Linear least squares for the initial states (free response, c = [1 0]) and the offset with the
// poles held: y[k] = Σ c Aᵢᵏ x0ᵢ + offset is linear in them (the x0 columns of the Jacobian).
void solve_amplitudes(detail::ModalModel& model, std::span<const double> y, bool with_offset) {
  const std::size_t n = y.size();
  const std::size_t total = detail::parameter_count(model);
  std::vector<double> out(n), jac(n * total);
  detail::simulate(model, {}, n, out.data(), jac.data());
  std::vector<std::size_t> cols;
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    const std::size_t p = detail::block_offset(model, b);
    if (model.blocks[b].complex) {
      cols.push_back(p + 4);
      cols.push_back(p + 5);
    } else {
      cols.push_back(p + 2);
    }
  }
  if (with_offset) cols.push_back(total - 1);
  Eigen::MatrixXd a(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t j = 0; j < cols.size(); ++j)
    for (std::size_t k = 0; k < n; ++k) a(static_cast<Eigen::Index>(k), static_cast<Eigen::Index>(j)) = jac[cols[j] * n + k];
  const Eigen::VectorXd rhs = Eigen::Map<const Eigen::VectorXd>(y.data(), static_cast<Eigen::Index>(n));
  const Eigen::VectorXd sol = a.colPivHouseholderQr().solve(rhs);
  std::vector<double> v = detail::pack(model);
  for (std::size_t j = 0; j < cols.size(); ++j) v[cols[j]] = sol(static_cast<Eigen::Index>(j));
  if (!with_offset) v[total - 1] = 0.0;
  detail::unpack(v, model);
}

double rms(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / static_cast<double>(v.size()));
}

ModeIdentification finish(const detail::ModalModel& model, const Eigen::MatrixXd& covariance, std::span<const double> input,
                          std::span<const double> y, double sample_time_s, const ModeOptions& options) {
  const std::size_t n = y.size();
  ModeIdentification out;
  out.sample_time_s = sample_time_s;
  std::vector<double> fitted(n);
  detail::simulate(model, input, n, fitted.data(), nullptr);
  out.fit_percent = metrics::fit_percent(y, fitted);
  out.rmse = metrics::rmse(y, fitted);
  out.fitted = UniformSeries{0.0, sample_time_s, fitted};
  std::vector<ModeEstimate> modes;
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    if (!model.blocks[b].complex) continue;
    ModeEstimate m = detail::mode_estimate(model, b, covariance, sample_time_s, input, n);
    if (m.damping_ratio < options.max_damping_ratio) modes.push_back(m);
  }
  std::stable_sort(modes.begin(), modes.end(),
                   [](const ModeEstimate& a, const ModeEstimate& b) { return a.rms_contribution > b.rms_contribution; });
  if (modes.empty()) {
    throw RuntimeError("no oscillatory mode with damping ratio below " + std::to_string(options.max_damping_ratio) +
                       " was found in the record; check the output column, the time window (use the free decay "
                       "after a move) or raise --max-damping.");
  }
  if (modes.size() > options.modes) modes.resize(options.modes);
  out.modes = std::move(modes);
  return out;
}

void check_free_response(const UniformSeries& response) {
  require_positive("response sample_time_s", response.sample_time_s);
  const std::size_t n = response.size();
  if (n < 50) {
    throw InvalidArgument("free response has " + std::to_string(n) + " samples; at least 50 are needed to identify modes.");
  }
  for (std::size_t k = 0; k < n; ++k) {
    if (!std::isfinite(response.values[k])) {
      throw InvalidArgument("free response sample " + std::to_string(k) + " is not finite; repair the record.");
    }
  }
  // The Hankel matrix and the decimation's spectrum sum products of samples (error.hpp).
  if (const std::size_t k = first_unsquarable(response.values); k < n) {
    throw InvalidArgument(fmt::format("free response sample {} (t = {:g} s) = {:g} is too large: its spectrum would "
                                      "overflow; allowed: |value| <= {:.3g} for a record of {} samples. Rescale the "
                                      "record (other units)", k, response.time_s(k), response.values[k],
                                      largest_squarable(n), n));
  }
}

// The ERA model's poles at the full rate, z = exp(log(z_q)/q), as modal blocks (no input). A
// real pole slower than the record of n samples is the constant offset when that is estimated.
detail::ModalModel full_rate_blocks(const FreeResponseModel& era_model, std::size_t q, std::size_t n,
                                    bool estimate_offset) {
  const linalg::EigenDecomposition es = linalg::eigen(era_model.a);
  detail::ModalModel model;
  model.has_input = false;
  for (Eigen::Index k = 0; k < es.values.size(); ++k) {
    const std::complex<double> zq = es.values(k);
    if (std::abs(zq) == 0.0) continue;
    const std::complex<double> z = std::exp(std::log(zq) / static_cast<double>(q));
    const double tol = 1e-10 * std::max(1.0, std::abs(z));
    detail::ModalBlock blk;
    if (z.imag() > tol) {
      blk.complex = true;
      blk.pole0 = std::log(std::abs(z));
      blk.pole1 = std::arg(z);
    } else if (std::abs(z.imag()) <= tol) {
      if (estimate_offset && std::abs(1.0 - z.real()) < 1.0 / static_cast<double>(n)) continue;
      blk.complex = false;
      blk.pole0 = z.real();
    } else {
      continue;
    }
    model.blocks.push_back(blk);
  }
  return model;
}

// The blocks whose energy Σ yᵢ² stands out of the noise (> 25 σ², σ² from the residual of the
// linear fit of `model`), and every block already marked in `keep`: spurious poles that only fit
// noise would leave the refinement without a unique optimum.
detail::ModalModel energetic_blocks(const detail::ModalModel& model, const std::vector<double>& y, std::vector<bool> keep) {
  const std::size_t n = y.size();
  std::vector<double> fitted(n);
  detail::simulate(model, {}, n, fitted.data(), nullptr);
  double sse = 0.0;
  for (std::size_t k = 0; k < n; ++k) sse += (y[k] - fitted[k]) * (y[k] - fitted[k]);
  const double sigma2 = sse / static_cast<double>(n);
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    const double r = rms(detail::block_output(model, b, {}, n));
    if (r * r * static_cast<double>(n) > 25.0 * sigma2) keep[b] = true;
  }
  detail::ModalModel kept;
  kept.has_input = false;
  for (std::size_t b = 0; b < model.blocks.size(); ++b)
    if (keep[b]) kept.blocks.push_back(model.blocks[b]);
  if (kept.blocks.empty()) {
    throw RuntimeError("no mode found in the free response (the record is flat or pure noise).");
  }
  return kept;
}

// The `modes` most energetic oscillatory blocks.
std::vector<bool> most_energetic(const detail::ModalModel& model, std::size_t count, std::size_t modes) {
  std::vector<double> energy;
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    const double r = rms(detail::block_output(model, b, {}, count));
    energy.push_back(r * r);
  }
  std::vector<std::size_t> complex_order;
  for (std::size_t b = 0; b < model.blocks.size(); ++b)
    if (model.blocks[b].complex) complex_order.push_back(b);
  std::stable_sort(complex_order.begin(), complex_order.end(),
                   [&](std::size_t a, std::size_t b) { return energy[a] > energy[b]; });
  std::vector<bool> keep(model.blocks.size(), false);
  for (std::size_t i = 0; i < complex_order.size() && i < modes; ++i) keep[complex_order[i]] = true;
  return keep;
}

// The persistent modes' poles at the diagram's chosen order: per persistent mode the nearest
// complex block within the frequency tolerance (ωn in rad per sample, |ln z|).
std::vector<bool> persistent_blocks(const detail::ModalModel& model, const StabilisationDiagram& diagram) {
  const double tol = diagram.options.frequency_tolerance;
  std::vector<bool> keep(model.blocks.size(), false);
  for (const PersistentMode& m : diagram.modes) {
    std::size_t best = model.blocks.size();
    double best_gap = tol * m.natural_frequency_rad_s;
    for (std::size_t b = 0; b < model.blocks.size(); ++b) {
      if (!model.blocks[b].complex) continue;
      const double gap = std::abs(std::hypot(model.blocks[b].pole0, model.blocks[b].pole1) - m.natural_frequency_rad_s);
      if (gap <= best_gap) {
        best = b;
        best_gap = gap;
      }
    }
    if (best < model.blocks.size()) keep[best] = true;
  }
  return keep;
}

StabilisationOptions diagram_options(const ModeOptions& options) {
  StabilisationOptions so = options.stabilisation;
  so.max_damping_ratio = options.max_damping_ratio;
  return so;
}

// The start of the free-response fit: ERA poles at the full rate with their amplitudes, the blocks
// that stand out of the noise, and how it was chosen (order, decimation, source).
struct FreeStart {
  detail::ModalModel model;
  std::size_t order = 0, decimation = 1;
  std::string order_source;
};

FreeStart diagram_start(const std::vector<double>& y, const StabilisationDiagram& d, const ModeOptions& options) {
  FreeStart s{{}, d.chosen_order, d.decimation, "stabilisation"};
  const std::vector<double> averaged = detail::block_average(y, d.decimation);
  const std::size_t rows = std::min(averaged.size() / 3, std::max<std::size_t>(4 * d.options.max_order, 40));
  detail::ModalModel model = full_rate_blocks(era(averaged, d.chosen_order, rows), d.decimation, y.size(), options.estimate_offset);
  solve_amplitudes(model, y, options.estimate_offset);
  // The persistent poles and those that stand out of the noise (a dominant mode whose subspace ζ
  // wanders more than the tolerance is still a mode); the others are the diagram's spurious poles.
  s.model = energetic_blocks(model, y, persistent_blocks(model, d));
  return s;
}

FreeStart modes_start(const std::vector<double>& y, const ModeOptions& options) {
  const std::size_t order = options.order > 0 ? options.order : 2 * options.modes + 2;
  // Block averaging keeps the poles (z^q) of a sum of exponentials and shortens the Hankel
  // matrix; the offset is one more pole, at z = 1, which the offset parameter then replaces.
  FreeStart s{{}, order, detail::choose_decimation(y, options.modes, order), options.order > 0 ? "option" : "modes"};
  const std::vector<double> averaged = detail::block_average(y, s.decimation);
  const std::size_t era_order = std::min(order + (options.estimate_offset ? 1 : 0), averaged.size() / 3 - 1);
  s.model = full_rate_blocks(era(averaged, era_order), s.decimation, y.size(), options.estimate_offset);
  solve_amplitudes(s.model, y, options.estimate_offset);
  s.model = energetic_blocks(s.model, y, most_energetic(s.model, y.size(), options.modes));
  return s;
}

}  // namespace

ModeIdentification identify_free_response_modes(const UniformSeries& response, const ModeOptions& options) {
  check_options(options);
  check_free_response(response);
  const std::vector<double>& y = response.values;
  StabilisationDiagram diagram;
  if (options.order == 0 && options.use_stabilisation) diagram = free_response_stabilisation(response, diagram_options(options));
  // The diagram's persistent poles in frequency per full-rate sample for the block match.
  StabilisationDiagram per_sample = diagram;
  for (PersistentMode& m : per_sample.modes) m.natural_frequency_rad_s *= response.sample_time_s;
  FreeStart start = diagram.modes.empty() ? modes_start(y, options) : diagram_start(y, per_sample, options);
  detail::ModalModel kept = start.model;
  solve_amplitudes(kept, y, options.estimate_offset);
  const std::vector<bool> free = detail::free_mask(kept, false, true, false, options.estimate_offset);
  Eigen::MatrixXd covariance;
  std::string method = "era";
  if (options.refine) {
    const detail::ModalFit fit = detail::refine(kept, {}, y, free, options.max_iterations);
    kept = fit.model;
    covariance = fit.covariance;
    method = "era+ls";
  } else {
    covariance = detail::covariance_at(kept, {}, y, free);
  }
  ModeIdentification out = finish(kept, covariance, {}, y, response.sample_time_s, options);
  out.fitted.start_s = response.start_s;  // on the record's grid: a window keeps its own start time
  out.decimation = start.decimation;
  out.method = method;
  out.order = start.order;
  out.order_source = start.order_source;
  out.stabilisation = std::move(diagram);
  return out;
}

namespace {

// Per persistent mode, the fitted mode nearest in frequency (within 5 tolerances: the output-error
// fit moves a subspace pole a little); the others are the spurious poles of the order.
std::vector<ModeEstimate> persistent_estimates(const std::vector<ModeEstimate>& all, const StabilisationDiagram& d) {
  std::vector<ModeEstimate> out;
  for (const PersistentMode& m : d.modes) {
    const ModeEstimate* best = nullptr;
    for (const ModeEstimate& e : all)
      if (matches(m, e.natural_frequency_rad_s, 5.0 * d.options.frequency_tolerance) &&
          (best == nullptr || std::abs(e.natural_frequency_rad_s - m.natural_frequency_rad_s) <
                                  std::abs(best->natural_frequency_rad_s - m.natural_frequency_rad_s)))
        best = &e;
    if (best != nullptr) out.push_back(*best);
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const ModeEstimate& a, const ModeEstimate& b) { return a.rms_contribution > b.rms_contribution; });
  return out;
}

// The output-error fit at the diagram's order; where it diverges, the next two orders up (they hold
// the persistent modes too), then the order from --modes (out.order and order_source say which).
StateSpaceEstimate diagram_fit(const Experiment& experiment, const StateSpaceFitOptions& so, std::size_t modes,
                               ModeIdentification& out) {
  for (std::size_t order = out.order; order <= out.order + 2 && order <= out.stabilisation.options.max_order; ++order) {
    try {
      StateSpaceEstimate est = estimate_state_space(experiment, order, so);
      out.order = order;
      return est;
    } catch (const RuntimeError&) {  // diverged at this order: try the next
    }
  }
  out.order = 2 * modes;
  out.order_source = "modes";
  return estimate_state_space(experiment, out.order, so);
}

}  // namespace

ModeIdentification identify_modes(const Experiment& experiment, const ModeOptions& options) {
  check_options(options);
  validate(experiment, 50);
  ModeIdentification out;
  if (options.order == 0 && options.use_stabilisation) out.stabilisation = input_output_stabilisation(experiment, diagram_options(options));
  const bool from_diagram = !out.stabilisation.modes.empty();
  out.order = options.order > 0 ? options.order : from_diagram ? out.stabilisation.chosen_order : 2 * options.modes;
  out.order_source = options.order > 0 ? "option" : from_diagram ? "stabilisation" : "modes";
  StateSpaceFitOptions so;
  so.refine = options.refine;
  so.initial_state = InitialState::estimate;
  so.max_iterations = options.max_iterations;
  const StateSpaceEstimate est = out.order_source == "stabilisation" ? diagram_fit(experiment, so, options.modes, out)
                                                                     : estimate_state_space(experiment, out.order, so);
  const std::size_t order = out.order;
  out.sample_time_s = experiment.sample_time_s;
  out.fit_percent = est.fit_percent;
  out.rmse = est.rmse;
  out.fitted = est.simulated;
  out.method = est.refined ? "n4sid+oe" : "n4sid";
  for (const ModeEstimate& m : out.order_source == "stabilisation" ? persistent_estimates(est.modes, out.stabilisation) : est.modes)
    if (m.damping_ratio < options.max_damping_ratio) out.modes.push_back(m);
  if (out.modes.empty()) {
    throw RuntimeError("no oscillatory mode with damping ratio below " + std::to_string(options.max_damping_ratio) +
                       " in the identified order-" + std::to_string(order) +
                       " model; raise the order (--order) or check the columns.");
  }
  if (out.modes.size() > options.modes) out.modes.resize(options.modes);
  return out;
}

}  // namespace clearshape::ident
