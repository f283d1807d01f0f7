#include "clearshape/lti/simulate.hpp"

#include <cmath>
#include <limits>
#include <string>

#include "clearshape/core/error.hpp"
#include "hold_integrals.hpp"

namespace clearshape::lti {

// ---------------------------------------------------------------- SampledModel

SampledModel::SampledModel(const ProcessModel& model, double sample_time_s, Hold hold)
    : SampledModel(model.state_space(), sample_time_s, hold, model.delay_s()) {}

SampledModel::SampledModel(const StateSpace& model, double sample_time_s, Hold hold, double delay_s)
    : continuous_(model), sample_time_s_(sample_time_s), hold_(hold), delay_s_(delay_s) {
  validate(model, true, "simulation model");
  require_positive("sample_time_s", sample_time_s, "The simulation sample time must be > 0.");
  require_non_negative("delay_s", delay_s, "An input delay cannot be negative.");
  const double samples = delay_s / sample_time_s;
  if (!(samples < 1e7)) {
    throw_invalid("delay_s / sample_time_s", samples, "< 1e7 samples", "Use a shorter delay or a longer sample time.");
  }
  // Td = (d + f)·T; a fraction within 1e-9 of an integer is snapped to it (rounding of Td/T).
  double whole = std::floor(samples);
  double fraction = samples - whole;
  if (fraction > 1.0 - 1e-9) {
    whole += 1.0;
    fraction = 0.0;
  } else if (fraction < 1e-9) {
    fraction = 0.0;
  }
  delay_samples_ = static_cast<std::size_t>(whole);
  delay_fraction_ = fraction;

  const Eigen::Index n = model.order();
  const double dd = model.d(0, 0);
  input_taps_ = Eigen::MatrixXd::Zero(n, 3);
  c_ = model.c;
  const double f = fraction;
  if (f == 0.0) {
    const auto in = detail::hold_integrals(model.a, model.b, sample_time_s);
    phi_ = in.phi;
    if (hold == Hold::zoh) {
      input_taps_.col(1) = in.gamma;  // x[k] = Φ x[k−1] + Γ u[k−1−d]
    } else {
      input_taps_.col(1) = in.gamma - in.lambda;  // linear from u[k−1−d] to u[k−d]
      input_taps_.col(0) = in.lambda;
    }
    output_taps_(0) = dd;  // y[k] = C x[k] + D u[k−d]
  } else {
    // The delayed input breaks at (k−1)T + fT: integrate [0, fT] then [fT, T] exactly.
    const auto p1 = detail::hold_integrals(model.a, model.b, f * sample_time_s);
    const auto p2 = detail::hold_integrals(model.a, model.b, (1.0 - f) * sample_time_s);
    phi_ = p2.phi * p1.phi;
    if (hold == Hold::zoh) {
      input_taps_.col(2) = p2.phi * p1.gamma;  // u[k−2−d] held on the first part
      input_taps_.col(1) = p2.gamma;           // u[k−1−d] on the second
      output_taps_(1) = dd;
    } else {
      // First part: from f·u[k−2−d] + (1−f)·u[k−1−d] to u[k−1−d]; second: from u[k−1−d] to
      // f·u[k−1−d] + (1−f)·u[k−d] (linear interpolation of the samples).
      const Eigen::MatrixXd g1 = p1.gamma - p1.lambda;
      const Eigen::MatrixXd g2 = p2.gamma - p2.lambda;
      input_taps_.col(2) = f * (p2.phi * g1);
      input_taps_.col(1) = p2.phi * ((1.0 - f) * g1 + p1.lambda) + g2 + f * p2.lambda;
      input_taps_.col(0) = (1.0 - f) * p2.lambda;
      output_taps_(1) = f * dd;
      output_taps_(0) = (1.0 - f) * dd;
    }
  }
}

// ---------------------------------------------------------------- Simulator

Simulator::Simulator(SampledModel model)
    : model_(std::move(model)),
      x_(Eigen::VectorXd::Zero(model_.order())),
      scratch_(Eigen::VectorXd::Zero(model_.order())),
      history_(model_.delay_samples() + 3, 0.0) {}

double Simulator::delayed(std::size_t lag) const noexcept {
  // lag < size: one conditional wrap instead of a division.
  return history_[head_ >= lag ? head_ - lag : head_ + history_.size() - lag];
}

Status Simulator::step(double input, double& output) noexcept {
  Status status = Status::ok;
  if (!std::isfinite(input)) {
    input = last_input_;
    status = Status::not_finite;
  }
  last_input_ = input;
  head_ = head_ + 1 == history_.size() ? 0 : head_ + 1;
  history_[head_] = input;
  const std::size_t d = model_.delay_samples();
  const Eigen::Vector3d lagged(delayed(d), delayed(d + 1), delayed(d + 2));
  if (steps_ > 0) {
    // x[k] = Φ x[k−1] + G·(u[k−d], u[k−d−1], u[k−d−2]); lazy products avoid Eigen's GEMV
    // dispatch, which dominates for the 1–6 states of a drive model.
    scratch_.noalias() = model_.phi().lazyProduct(x_) + model_.input_taps().lazyProduct(lagged);
    x_.swap(scratch_);
  }
  ++steps_;
  if (failed_ || !x_.allFinite()) {
    failed_ = true;
    output = std::numeric_limits<double>::quiet_NaN();
    return Status::not_finite;
  }
  output = model_.c().row(0).dot(x_) + model_.output_taps().dot(lagged);
  return status;
}

double Simulator::step(double input) noexcept {
  double y = 0.0;
  (void)step(input, y);  // y is NaN after a failure
  return y;
}

void Simulator::reset(double input_before_start) noexcept {
  x_.setZero();
  for (double& v : history_) v = input_before_start;
  head_ = 0;
  steps_ = 0;
  last_input_ = input_before_start;
  failed_ = false;
}

Status Simulator::reset(const Eigen::Ref<const Eigen::VectorXd>& x0, double input_before_start) noexcept {
  if (x0.size() != x_.size()) return Status::out_of_range;
  reset(input_before_start);
  x_ = x0;
  return Status::ok;
}

// ---------------------------------------------------------------- offline

UniformSeries simulate(const SampledModel& model, const UniformSeries& input, const Eigen::VectorXd& x0,
                       double input_before_start) {
  const double dt = model.sample_time_s();
  if (std::abs(input.sample_time_s - dt) > 1e-9 * dt) {
    throw_invalid("input sample_time_s", input.sample_time_s, std::to_string(dt) + " (the model's sample time)",
                  "Build the SampledModel with the input's sample time.");
  }
  require_finite("input_before_start", input_before_start);
  for (std::size_t i = 0; i < input.size(); ++i) {
    if (!std::isfinite(input.values[i])) {
      throw InvalidArgument("simulate: input sample " + std::to_string(i) + " (t = " +
                            std::to_string(input.time_s(i)) + " s) is not finite; every input value must be finite.");
    }
  }
  Simulator sim(model);
  if (x0.size() != 0) {
    if (sim.reset(x0, input_before_start) != Status::ok) {
      throw_invalid("simulate: x0 size", static_cast<double>(x0.size()),
                    std::to_string(model.order()) + " (the model order)");
    }
  } else {
    sim.reset(input_before_start);
  }
  UniformSeries out{input.start_s, input.sample_time_s, std::vector<double>(input.size())};
  for (std::size_t i = 0; i < input.size(); ++i) {
    if (sim.step(input.values[i], out.values[i]) != Status::ok) {
      throw RuntimeError("simulate: the state became non-finite at sample " + std::to_string(i) + " (t = " +
                         std::to_string(input.time_s(i)) + " s); the model or input diverges.");
    }
  }
  return out;
}

UniformSeries simulate(const StateSpace& model, const UniformSeries& input, Hold hold, double delay_s,
                       const Eigen::VectorXd& x0) {
  return simulate(SampledModel(model, input.sample_time_s, hold, delay_s), input, x0);
}

UniformSeries simulate(const ProcessModel& model, const UniformSeries& input, Hold hold) {
  return simulate(SampledModel(model, input.sample_time_s, hold), input);
}

UniformSeries simulate(const TransferFunction& model, const UniformSeries& input, Hold hold) {
  return simulate(SampledModel(model.state_space(), input.sample_time_s, hold), input);
}

namespace {
UniformSeries step_input(double duration_s, double sample_time_s, double amplitude) {
  require_finite("amplitude", amplitude);
  return UniformSeries{0.0, sample_time_s, std::vector<double>(sample_count(duration_s, sample_time_s), amplitude)};
}
}  // namespace

UniformSeries step_response(const ProcessModel& model, double duration_s, double sample_time_s, double amplitude) {
  return simulate(model, step_input(duration_s, sample_time_s, amplitude), Hold::zoh);
}
UniformSeries step_response(const TransferFunction& model, double duration_s, double sample_time_s,
                            double amplitude) {
  return simulate(model, step_input(duration_s, sample_time_s, amplitude), Hold::zoh);
}
UniformSeries step_response(const StateSpace& model, double duration_s, double sample_time_s, double amplitude) {
  return simulate(model, step_input(duration_s, sample_time_s, amplitude), Hold::zoh);
}

}  // namespace clearshape::lti
