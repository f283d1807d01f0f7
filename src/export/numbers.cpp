#include "clearshape/export/numbers.hpp"

#include <cmath>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"

namespace clearshape::exports {
namespace {

// "1" → "1.0": a C literal without '.' or exponent would be an integer ("1f" does not parse).
std::string with_point(std::string s) {
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

}  // namespace

std::string shortest(double x) { return with_point(fmt::format("{}", x)); }

std::string shortest(float x) { return with_point(fmt::format("{}", x)); }

double round_significant(double x, int digits) {
  if (!std::isfinite(x) || x == 0.0) return x;
  // Scientific notation with digits−1 decimals is exactly "digits significant digits".
  return std::stod(fmt::format("{:.{}e}", x, digits - 1));
}

std::string fixed_significant(double x, int digits) {
  require_finite("number to format", x);
  require_in_closed("significant digits", digits, 1, 17);
  const double r = round_significant(x, digits);
  if (r == 0.0) return "0";
  const int exponent = static_cast<int>(std::floor(std::log10(std::abs(r))));
  const int decimals = std::max(0, digits - 1 - exponent);
  std::string s = fmt::format("{:.{}f}", r, decimals);
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  return s;
}

}  // namespace clearshape::exports
