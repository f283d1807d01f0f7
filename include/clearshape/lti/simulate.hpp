#pragma once
// Exact sampled simulation of a SISO continuous model with an input delay.
//
// The input samples u[k] (at t = kT) are reconstructed by a hold (ZOH: piecewise constant;
// FOH: piecewise linear), delayed by Td = (d + f)·T (d integer, 0 ≤ f < 1), and integrated
// exactly. Integer-sample delays are a pure shift. For a fractional delay the delayed input has
// its breakpoints inside the sample interval, at kT + fT; the interval is split there and each
// part integrated exactly (matrix exponential), the delayed input's values at the split points
// being linear interpolations of the samples (FOH) or the held sample (ZOH). So the result is
// exact for the held input at any delay (the modified z-transform of Franklin, Powell & Workman,
// "Digital Control of Dynamic Systems"; integrals by Van Loan 1978, see discretize.hpp).
// Samples before the start take the value `input_before_start` (default 0).
//
// Per sample: x[k] = Φ x[k−1] + Σⱼ Gⱼ u[k−d−j],  y[k] = C x[k] + Σⱼ Hⱼ u[k−d−j],  j = 0, 1, 2.
#include <cstddef>
#include <span>
#include <vector>

#include <Eigen/Dense>

#include "clearshape/core/series.hpp"
#include "clearshape/core/status.hpp"
#include "clearshape/lti/discretize.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/lti/state_space.hpp"

namespace clearshape::lti {

/// The design: an immutable sampled model (Φ, input taps, output taps) built at configuration
/// time. Throws InvalidArgument on a non-SISO model, a bad sample time or delay.
class SampledModel {
 public:
  SampledModel(const StateSpace& model, double sample_time_s, Hold hold = Hold::zoh,
               double delay_s = 0.0);
  /// Cascade realization of the process model with its delay Td.
  SampledModel(const ProcessModel& model, double sample_time_s, Hold hold = Hold::zoh);

  Eigen::Index order() const noexcept { return phi_.rows(); }
  double sample_time_s() const noexcept { return sample_time_s_; }
  Hold hold() const noexcept { return hold_; }
  double delay_s() const noexcept { return delay_s_; }
  std::size_t delay_samples() const noexcept { return delay_samples_; }  ///< d
  double delay_fraction() const noexcept { return delay_fraction_; }     ///< f
  const Eigen::MatrixXd& phi() const noexcept { return phi_; }           ///< e^(AT)
  const Eigen::MatrixXd& input_taps() const noexcept { return input_taps_; }  ///< n×3: G0 G1 G2
  const Eigen::MatrixXd& c() const noexcept { return c_; }                    ///< 1×n
  const Eigen::Vector3d& output_taps() const noexcept { return output_taps_; }  ///< H0 H1 H2
  /// The continuous model it was built from.
  const StateSpace& continuous() const noexcept { return continuous_; }

 private:
  StateSpace continuous_;
  double sample_time_s_ = 0.0;
  Hold hold_ = Hold::zoh;
  double delay_s_ = 0.0;
  std::size_t delay_samples_ = 0;
  double delay_fraction_ = 0.0;
  Eigen::MatrixXd phi_;
  Eigen::MatrixXd input_taps_;
  Eigen::MatrixXd c_;
  Eigen::Vector3d output_taps_ = Eigen::Vector3d::Zero();
};

/// The state: runs a SampledModel one sample at a time. All memory is allocated at
/// construction; step() and reset() are noexcept and allocation-free (real-time safe).
class Simulator {
 public:
  explicit Simulator(SampledModel model);

  /// Feeds u[k] and writes y[k]. The first call after construction/reset returns
  /// y[0] = C x0 + D·(delayed input at t0); every later call first advances the state by one
  /// sample. A non-finite input is replaced by the previous one (Status::not_finite); a
  /// non-finite state gives Status::not_finite and y = NaN until reset.
  Status step(double input, double& output) noexcept;
  /// Convenience form for trusted input (NaN on failure).
  double step(double input) noexcept;
  /// Zero state; input history = input_before_start.
  void reset(double input_before_start = 0.0) noexcept;
  /// Given state x0 (size order(), else Status::out_of_range and nothing changes).
  Status reset(const Eigen::Ref<const Eigen::VectorXd>& x0, double input_before_start = 0.0) noexcept;

  const SampledModel& model() const noexcept { return model_; }
  /// x at the time of the last output (x0 before the first step).
  const Eigen::VectorXd& state() const noexcept { return x_; }
  std::size_t steps() const noexcept { return steps_; }

 private:
  double delayed(std::size_t lag) const noexcept;  // u[k − lag] from the ring buffer

  SampledModel model_;
  Eigen::VectorXd x_;
  Eigen::VectorXd scratch_;
  std::vector<double> history_;  // ring buffer of the last d + 3 inputs
  std::size_t head_ = 0;         // index of the newest input
  std::size_t steps_ = 0;
  double last_input_ = 0.0;
  bool failed_ = false;
};

/// Offline simulation on the input's time grid (same start and sample time). `x0` empty = 0.
UniformSeries simulate(const SampledModel& model, const UniformSeries& input,
                       const Eigen::VectorXd& x0 = {}, double input_before_start = 0.0);
/// As scipy.signal.lsim: Hold::zoh ↔ interp=False, Hold::foh ↔ interp=True.
UniformSeries simulate(const StateSpace& model, const UniformSeries& input, Hold hold = Hold::zoh,
                       double delay_s = 0.0, const Eigen::VectorXd& x0 = {});
UniformSeries simulate(const ProcessModel& model, const UniformSeries& input, Hold hold = Hold::zoh);
UniformSeries simulate(const TransferFunction& model, const UniformSeries& input, Hold hold = Hold::zoh);

/// Response to a step of `amplitude` applied at t = 0, sampled at t = 0, T, … up to duration_s
/// (exact: the step is held). Delay included for process models.
UniformSeries step_response(const ProcessModel& model, double duration_s, double sample_time_s,
                            double amplitude = 1.0);
UniformSeries step_response(const TransferFunction& model, double duration_s, double sample_time_s,
                            double amplitude = 1.0);
UniformSeries step_response(const StateSpace& model, double duration_s, double sample_time_s,
                            double amplitude = 1.0);

}  // namespace clearshape::lti
