#pragma once
// One input/output record on a uniform time grid: the data that identification works on.
#include <cstddef>
#include <span>
#include <string>
#include <vector>

#include "clearshape/core/series.hpp"

namespace clearshape::ident {

struct Experiment {
  std::string name;            ///< label in reports (file name, input type)
  double sample_time_s = 0.0;  ///< > 0
  std::vector<double> input;   ///< u[k] at t = k·T (command units)
  std::vector<double> output;  ///< y[k] at t = k·T (output units), same length

  std::size_t size() const noexcept { return output.size(); }
  double duration_s() const noexcept;
  UniformSeries input_series() const;
  UniformSeries output_series() const;
};

/// Builds an experiment from two series on the same grid (same start, sample time and length).
/// Throws InvalidArgument otherwise.
Experiment make_experiment(std::string name, const UniformSeries& input, const UniformSeries& output);

/// Checks a positive sample time, equal lengths ≥ min_samples and finite values; throws
/// InvalidArgument naming the experiment, the sample index and the remedy.
void validate(const Experiment& experiment, std::size_t min_samples = 10);

/// Samples [first, last) of an experiment (for estimation/validation splits).
Experiment slice(const Experiment& experiment, std::size_t first, std::size_t last);

}  // namespace clearshape::ident
