#include "clearshape/ident/modes.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/dsp/peaks.hpp"
#include "clearshape/dsp/welch.hpp"
#include "clearshape/ident/state_space_fit.hpp"
#include "clearshape/ident/subspace.hpp"
#include "clearshape/metrics/fit.hpp"
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

// Block-averaging factor for the subspace step: ≥ 10 samples per period of the highest of the
// dominant spectral peaks (Welch, mean removed per segment), and ≥ max(60, 6·order) averaged
// samples.
std::size_t choose_decimation(const std::vector<double>& v, std::size_t modes, std::size_t order) {
  const std::size_t n = v.size();
  std::size_t seg = 1;
  while (seg * 2 <= std::min<std::size_t>(n, 2048)) seg *= 2;
  if (seg < 16) return 1;
  dsp::WelchOptions wo;
  wo.segment_length = seg;
  const dsp::Spectrum spec = dsp::welch(v, 1.0, wo);  // frequency in cycles/sample
  const auto peaks = dsp::spectral_peaks(spec, {}, modes);
  double f_hi = 0.0;
  for (const auto& p : peaks) f_hi = std::max(f_hi, p.interpolated_frequency_hz);
  if (!(f_hi > 0.0)) return 1;
  std::size_t q = static_cast<std::size_t>(std::floor(1.0 / (10.0 * f_hi)));
  const std::size_t q_max = n / std::max<std::size_t>(60, 6 * order);
  q = std::min(q, q_max);
  return std::max<std::size_t>(q, 1);
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
}

// Means of consecutive blocks of q samples (a last partial block is dropped).
std::vector<double> block_average(const std::vector<double>& y, std::size_t q) {
  std::vector<double> averaged;
  for (std::size_t k = 0; (k + 1) * q <= y.size(); ++k) {
    double s = 0.0;
    for (std::size_t j = 0; j < q; ++j) s += y[k * q + j];
    averaged.push_back(s / static_cast<double>(q));
  }
  return averaged;
}

// The ERA model's poles at the full rate, z = exp(log(z_q)/q), as modal blocks (no input). A
// real pole slower than the record of n samples is the constant offset when that is estimated.
detail::ModalModel full_rate_blocks(const FreeResponseModel& era_model, std::size_t q, std::size_t n,
                                    bool estimate_offset) {
  Eigen::EigenSolver<Eigen::MatrixXd> es(era_model.a, false);
  detail::ModalModel model;
  model.has_input = false;
  for (Eigen::Index k = 0; k < es.eigenvalues().size(); ++k) {
    const std::complex<double> zq = es.eigenvalues()(k);
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

// Keep the `modes` most energetic oscillatory blocks, and any other block whose energy Σ yᵢ²
// stands out of the noise (> 25 σ², σ² from the residual of the linear fit of `model`):
// spurious poles that only fit noise would leave the refinement without a unique optimum.
detail::ModalModel energetic_blocks(const detail::ModalModel& model, const std::vector<double>& y, std::size_t modes) {
  const std::size_t n = y.size();
  std::vector<double> fitted(n);
  detail::simulate(model, {}, n, fitted.data(), nullptr);
  double sse = 0.0;
  for (std::size_t k = 0; k < n; ++k) sse += (y[k] - fitted[k]) * (y[k] - fitted[k]);
  const double sigma2 = sse / static_cast<double>(n);
  std::vector<double> energy;
  for (std::size_t b = 0; b < model.blocks.size(); ++b) {
    const double r = rms(detail::block_output(model, b, {}, n));
    energy.push_back(r * r * static_cast<double>(n));
  }
  std::vector<std::size_t> complex_order;
  for (std::size_t b = 0; b < model.blocks.size(); ++b)
    if (model.blocks[b].complex) complex_order.push_back(b);
  std::stable_sort(complex_order.begin(), complex_order.end(),
                   [&](std::size_t a, std::size_t b) { return energy[a] > energy[b]; });
  std::vector<bool> keep(model.blocks.size(), false);
  for (std::size_t i = 0; i < complex_order.size() && i < modes; ++i) keep[complex_order[i]] = true;
  for (std::size_t b = 0; b < model.blocks.size(); ++b)
    if (energy[b] > 25.0 * sigma2) keep[b] = true;
  detail::ModalModel kept;
  kept.has_input = false;
  for (std::size_t b = 0; b < model.blocks.size(); ++b)
    if (keep[b]) kept.blocks.push_back(model.blocks[b]);
  if (kept.blocks.empty()) {
    throw RuntimeError("no mode found in the free response (the record is flat or pure noise).");
  }
  return kept;
}

}  // namespace

ModeIdentification identify_free_response_modes(const UniformSeries& response, const ModeOptions& options) {
  check_options(options);
  check_free_response(response);
  const std::vector<double>& y = response.values;
  const std::size_t order = options.order > 0 ? options.order : 2 * options.modes + 2;
  // Block averaging keeps the poles (z^q) of a sum of exponentials and shortens the Hankel
  // matrix; the offset is one more pole, at z = 1, which the offset parameter then replaces.
  const std::size_t q = choose_decimation(y, options.modes, order);
  const std::vector<double> averaged = block_average(y, q);
  const std::size_t era_order = std::min(order + (options.estimate_offset ? 1 : 0), averaged.size() / 3 - 1);
  detail::ModalModel model = full_rate_blocks(era(averaged, era_order), q, y.size(), options.estimate_offset);
  solve_amplitudes(model, y, options.estimate_offset);
  detail::ModalModel kept = energetic_blocks(model, y, options.modes);
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
  out.decimation = q;
  out.method = method;
  return out;
}

ModeIdentification identify_modes(const Experiment& experiment, const ModeOptions& options) {
  check_options(options);
  validate(experiment, 50);
  const std::size_t order = options.order > 0 ? options.order : 2 * options.modes;
  StateSpaceFitOptions so;
  so.refine = options.refine;
  so.initial_state = InitialState::estimate;
  so.max_iterations = options.max_iterations;
  const StateSpaceEstimate est = estimate_state_space(experiment, order, so);
  ModeIdentification out;
  out.sample_time_s = experiment.sample_time_s;
  out.fit_percent = est.fit_percent;
  out.rmse = est.rmse;
  out.fitted = est.simulated;
  out.method = est.refined ? "n4sid+oe" : "n4sid";
  for (const ModeEstimate& m : est.modes)
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
