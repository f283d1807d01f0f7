#pragma once
// Internal pieces of the process-model fit: parameter layout and data-derived starting points.
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "clearshape/ident/experiment.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/lti/process_model.hpp"

namespace clearshape::ident::detail {

/// Number of states of the cascade realization when every time constant is > 0.
int process_order(const lti::ProcessStructure& s);

/// Optimizer layout: which parameters are free, how they are scaled, their bounds.
struct Layout {
  lti::ProcessStructure structure;
  std::vector<std::string> names;     ///< parameter_names()
  std::vector<double> fixed_value;    ///< NaN for free parameters
  std::vector<int> free;              ///< optimizer slot → parameter index
  std::vector<bool> log_scale;        ///< per parameter: optimised as its logarithm
  std::vector<double> lower, upper;   ///< natural units, per parameter
  std::vector<std::optional<double>> initial;
  int kp = -1, tz = -1, td = -1, zeta = -1;

  /// Full parameter values from optimizer variables.
  std::vector<double> values(const double* theta) const;
  /// ∂value/∂θ for each slot.
  std::vector<double> chain(const double* theta) const;
  /// Optimizer variables from full values.
  std::vector<double> theta(std::span<const double> values) const;
  bool is_fixed(int parameter) const;
};

Layout make_layout(const lti::ProcessStructure& s, const ProcessFitOptions& options, double max_delay_s);

/// Data-derived pole configurations (starting values with Kp = 1 and Tz = 0, which the fit then frees; Td included): step response
/// overshoot and peak time, N4SID models at a few decimations, and a log-spaced grid of time scales.
std::vector<std::vector<double>> candidate_values(const Layout& layout, std::span<const Experiment> experiments);

/// The canonical one of equivalent parameter sets: free real time constants in descending order
/// (Tp1 ≥ Tp2 ≥ Tp3); for P3U with Zeta > 1 (three real poles), the pair made of the two closest
/// poles. Values that bounds forbid are left as they are.
std::vector<double> canonical(const Layout& layout, std::vector<double> values);

/// Robust white-noise standard deviation of a record (MAD of second differences).
double noise_level(std::span<const double> y);

/// The level test of InitialState::automatic: y[0] at the rest level (0, or y[0] itself with an
/// output offset) within max(2 % of the range, 4σ).
bool starts_at_rest(std::span<const double> y, bool relative_to_first);

}  // namespace clearshape::ident::detail
