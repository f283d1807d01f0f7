#include "clearshape/core/error.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include <fmt/format.h>

namespace clearshape {

namespace {
std::string input_message(const std::string& file, std::size_t line, const std::string& field,
                          const std::string& problem) {
  std::string where = file;
  if (line > 0) where += fmt::format(":{}", line);
  if (!field.empty()) where += fmt::format(": field '{}'", field);
  return fmt::format("{}: {}", where, problem);
}

std::string with_remedy(std::string message, std::string_view remedy) {
  if (!remedy.empty()) {
    message += ". ";
    message += remedy;
  }
  return message;
}
}  // namespace

InputError::InputError(std::string file, std::size_t line, std::string field,
                       const std::string& problem)
    : std::runtime_error(input_message(file, line, field, problem)),
      file_(std::move(file)),
      line_(line),
      field_(std::move(field)) {}

void throw_invalid(std::string_view parameter, double value, std::string_view allowed,
                   std::string_view remedy) {
  throw InvalidArgument(
      with_remedy(fmt::format("{} = {} is out of range; allowed: {}", parameter, value, allowed),
                  remedy));
}

void require_finite(std::string_view parameter, double value) {
  if (!std::isfinite(value)) throw_invalid(parameter, value, "a finite number");
}

void require_positive(std::string_view parameter, double value, std::string_view remedy) {
  if (!(std::isfinite(value) && value > 0.0)) throw_invalid(parameter, value, "finite and > 0", remedy);
}

void require_non_negative(std::string_view parameter, double value, std::string_view remedy) {
  if (!(std::isfinite(value) && value >= 0.0)) {
    throw_invalid(parameter, value, "finite and >= 0", remedy);
  }
}

void require_in_closed(std::string_view parameter, double value, double lo, double hi,
                       std::string_view remedy) {
  if (!(std::isfinite(value) && value >= lo && value <= hi)) {
    throw_invalid(parameter, value, fmt::format("[{}, {}]", lo, hi), remedy);
  }
}

void require_in_half_open(std::string_view parameter, double value, double lo, double hi,
                          std::string_view remedy) {
  if (!(std::isfinite(value) && value >= lo && value < hi)) {
    throw_invalid(parameter, value, fmt::format("[{}, {})", lo, hi), remedy);
  }
}

void require_in_open(std::string_view parameter, double value, double lo, double hi,
                     std::string_view remedy) {
  if (!(std::isfinite(value) && value > lo && value < hi)) {
    throw_invalid(parameter, value, fmt::format("({}, {})", lo, hi), remedy);
  }
}

double largest_squarable(std::size_t samples) noexcept {
  return std::sqrt(std::numeric_limits<double>::max()) / static_cast<double>(std::max<std::size_t>(samples, 1));
}

std::size_t first_unsquarable(std::span<const double> values) noexcept {
  const double limit = largest_squarable(values.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (!(std::abs(values[i]) <= limit)) return i;
  }
  return values.size();
}

}  // namespace clearshape
