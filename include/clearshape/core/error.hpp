#pragma once
// Error types and boundary validation (docs/design.md §3–4).
// Configuration-time code throws; real-time code returns clearshape::Status instead.
//   InvalidArgument  a parameter outside its allowed range   -> CLI exit code 2
//   InputError       bad data in an input file (file, line, field) -> CLI exit code 2
//   RuntimeError     a failure while computing (divergence, I/O)  -> CLI exit code 1
#include <cstddef>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

namespace clearshape {

class InvalidArgument : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

class InputError : public std::runtime_error {
 public:
  /// `line` is 1-based; 0 means "the whole file". `field` may be empty.
  InputError(std::string file, std::size_t line, std::string field, const std::string& problem);
  const std::string& file() const noexcept { return file_; }
  std::size_t line() const noexcept { return line_; }
  const std::string& field() const noexcept { return field_; }

 private:
  std::string file_;
  std::size_t line_;
  std::string field_;
};

class RuntimeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Throws InvalidArgument: "<parameter> = <value> is out of range; allowed: <allowed>. <remedy>"
[[noreturn]] void throw_invalid(std::string_view parameter, double value, std::string_view allowed,
                                std::string_view remedy = {});

/// Requires a finite value.
void require_finite(std::string_view parameter, double value);
/// Requires a finite value > 0.
void require_positive(std::string_view parameter, double value, std::string_view remedy = {});
/// Requires a finite value >= 0.
void require_non_negative(std::string_view parameter, double value, std::string_view remedy = {});
/// Requires lo <= value <= hi (closed interval).
void require_in_closed(std::string_view parameter, double value, double lo, double hi,
                       std::string_view remedy = {});
/// Requires lo <= value < hi (half-open interval).
void require_in_half_open(std::string_view parameter, double value, double lo, double hi,
                          std::string_view remedy = {});
/// Requires lo < value < hi (open interval).
void require_in_open(std::string_view parameter, double value, double lo, double hi,
                     std::string_view remedy = {});

/// The largest |value| a record of `samples` samples may hold so that no sum of products of its
/// samples (a power spectrum, a covariance, a Hankel matrix's norm) overflows: √DBL_MAX / samples
/// (|Σ x_i y_i| ≤ n·max², so n·max ≤ √DBL_MAX keeps every such sum finite, even squared).
double largest_squarable(std::size_t samples) noexcept;
/// Index of the first sample beyond largest_squarable(values.size()), or values.size() if none.
std::size_t first_unsquarable(std::span<const double> values) noexcept;

}  // namespace clearshape
