#pragma once
// Input checks shared by the metrics (internal header).
#include <cmath>
#include <cstddef>
#include <span>
#include <string>
#include <string_view>

#include "clearshape/core/error.hpp"

namespace clearshape::metrics::detail {

inline void require_finite_samples(std::string_view name, std::span<const double> values) {
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values[i])) {
      throw InvalidArgument(std::string(name) + "[" + std::to_string(i) + "] = " +
                            std::to_string(values[i]) +
                            " is not finite; allowed: finite numbers. Remove or interpolate "
                            "the NaN/Inf samples first");
    }
  }
}

inline void require_min_size(std::string_view name, std::size_t size, std::size_t minimum) {
  if (size < minimum) {
    throw InvalidArgument(std::string(name) + " has " + std::to_string(size) +
                          " samples; allowed: at least " + std::to_string(minimum) +
                          ". Record a longer signal");
  }
}

inline void require_same_size(std::string_view a, std::size_t size_a, std::string_view b,
                              std::size_t size_b) {
  if (size_a != size_b) {
    throw InvalidArgument(std::string(a) + " has " + std::to_string(size_a) + " samples but " +
                          std::string(b) + " has " + std::to_string(size_b) +
                          "; allowed: equal lengths. Resample both on the same time grid");
  }
}

}  // namespace clearshape::metrics::detail
