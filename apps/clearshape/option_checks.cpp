#include "option_checks.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <string>

#include <fmt/format.h>

namespace clearshape::cli {

namespace {

// strtod accepts "nan", "inf", "infinity" in any case, the values CLI11 would pass on.
std::string finite_number(std::string& text) {
  if (text.empty()) return {};
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (end != text.c_str() && !std::isfinite(v)) return fmt::format("{} is not a finite number", text);
  return {};
}

std::string not_negative(std::string& text) {
  const auto first = text.find_first_not_of(" \t");
  if (first != std::string::npos && text[first] == '-') {
    return fmt::format("{} is negative; allowed: 0 … {}", text,
                       std::numeric_limits<unsigned long long>::max());
  }
  return {};
}

}  // namespace

CLI::Validator positive_at_most(double max, const std::string& unit, const std::string& option) {
  return CLI::Validator(
      [max, unit, option](std::string& text) -> std::string {
        char* end = nullptr;
        const double v = std::strtod(text.c_str(), &end);
        if (end == text.c_str()) return {};  // not a number: CLI11's conversion names it
        if (!(v > 0.0 && v <= max)) {
          return fmt::format("{} is out of range; allowed: (0, {:g}] {} (omit {} for none)", text, max, unit, option);
        }
        return {};
      },
      "", "POSITIVE");
}

void add_common_option_checks(CLI::App& app) {
  for (CLI::Option* opt : app.get_options()) {
    const std::string type = opt->get_type_name();
    if (type.find("FLOAT") != std::string::npos) {
      opt->check(CLI::Validator(finite_number, "", "FINITE"));
    } else if (type.find("UINT") != std::string::npos) {
      opt->check(CLI::Validator(not_negative, "", "NON-NEGATIVE"));
    }
  }
  for (CLI::App* sub : app.get_subcommands({})) add_common_option_checks(*sub);
}

}  // namespace clearshape::cli
