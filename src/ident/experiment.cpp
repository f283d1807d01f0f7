#include "clearshape/ident/experiment.hpp"

#include <cmath>
#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::ident {

double Experiment::duration_s() const noexcept {
  return output.empty() ? 0.0 : static_cast<double>(output.size() - 1) * sample_time_s;
}

UniformSeries Experiment::input_series() const { return UniformSeries{0.0, sample_time_s, input}; }
UniformSeries Experiment::output_series() const { return UniformSeries{0.0, sample_time_s, output}; }

Experiment make_experiment(std::string name, const UniformSeries& input, const UniformSeries& output) {
  if (input.size() != output.size()) {
    throw InvalidArgument("experiment \"" + name + "\": input has " + std::to_string(input.size()) +
                          " samples and output " + std::to_string(output.size()) +
                          "; they must be recorded on the same grid.");
  }
  if (std::abs(input.sample_time_s - output.sample_time_s) > 1e-9 * output.sample_time_s ||
      std::abs(input.start_s - output.start_s) > 1e-9 * output.sample_time_s) {
    throw InvalidArgument("experiment \"" + name + "\": input and output have different time grids (start " +
                          std::to_string(input.start_s) + " vs " + std::to_string(output.start_s) +
                          " s, sample time " + std::to_string(input.sample_time_s) + " vs " +
                          std::to_string(output.sample_time_s) + " s); resample them to one grid.");
  }
  return Experiment{std::move(name), output.sample_time_s, input.values, output.values};
}

void validate(const Experiment& e, std::size_t min_samples) {
  const std::string label = "experiment \"" + e.name + "\"";
  require_positive(label + " sample_time_s", e.sample_time_s, "Give the sample time of the record in seconds.");
  if (e.input.size() != e.output.size()) {
    throw InvalidArgument(label + ": input has " + std::to_string(e.input.size()) + " samples and output " +
                          std::to_string(e.output.size()) + "; they must have the same length.");
  }
  if (e.output.size() < min_samples) {
    throw InvalidArgument(label + " has " + std::to_string(e.output.size()) + " samples; at least " +
                          std::to_string(min_samples) + " are needed. Record a longer run.");
  }
  for (std::size_t k = 0; k < e.output.size(); ++k) {
    if (!std::isfinite(e.input[k]) || !std::isfinite(e.output[k])) {
      throw InvalidArgument(label + ": sample " + std::to_string(k) + " (t = " +
                            std::to_string(static_cast<double>(k) * e.sample_time_s) +
                            " s) is not finite; remove or repair it.");
    }
  }
}

Experiment slice(const Experiment& e, std::size_t first, std::size_t last) {
  if (!(first < last && last <= e.output.size())) {
    throw InvalidArgument("slice of experiment \"" + e.name + "\": [" + std::to_string(first) + ", " +
                          std::to_string(last) + ") is out of range; allowed: first < last <= " +
                          std::to_string(e.output.size()) + ".");
  }
  Experiment out;
  out.name = e.name;
  out.sample_time_s = e.sample_time_s;
  out.input.assign(e.input.begin() + static_cast<std::ptrdiff_t>(first),
                   e.input.begin() + static_cast<std::ptrdiff_t>(last));
  out.output.assign(e.output.begin() + static_cast<std::ptrdiff_t>(first),
                    e.output.begin() + static_cast<std::ptrdiff_t>(last));
  return out;
}

}  // namespace clearshape::ident
