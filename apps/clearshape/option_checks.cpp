#include "option_checks.hpp"

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <string>

#include <fmt/format.h>

#include "clearshape/io/atomic_file.hpp"

namespace clearshape::cli {

namespace {

// An empty value (`--max-delay-s ""`) would be read as 0 by CLI11's conversion.
std::string not_empty(std::string& text) {
  if (text.find_first_not_of(" \t") == std::string::npos) return "an empty value is not a number; give one";
  return {};
}

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
    return fmt::format("{} is negative; allowed: a whole number >= 0", text);
  }
  return {};
}

// CLI11's PositiveNumber / NonNegativeNumber state their bound as DBL_MAX written out in full (a
// 309-digit number); the same check, stated as the range it is.
void restate_sign_checks(CLI::Option& opt) {
  for (int i = 0;; ++i) {
    CLI::Validator* v = nullptr;
    try {
      v = opt.get_validator(i);
    } catch (const CLI::OptionNotFound&) {
      return;
    }
    // CLI11 gives these two their name as the description, not as the name.
    const std::string desc = v->get_description();
    if (desc != "POSITIVE" && desc != "NONNEGATIVE") continue;
    const bool strict = desc == "POSITIVE";
    v->operation([strict](std::string& text) -> std::string {
      char* end = nullptr;
      const double x = std::strtod(text.c_str(), &end);
      if (end == text.c_str()) return fmt::format("{} is not a number", text);
      if (strict ? !(x > 0.0) : !(x >= 0.0)) {
        return fmt::format("{} is out of range; allowed: {}", text, strict ? "> 0" : ">= 0");
      }
      return {};
    });
  }
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

CLI::Validator output_folder() {
  return CLI::Validator(
      [](std::string& text) -> std::string {
        const std::string problem = io::folder_problem(text);
        return problem.empty() ? problem : problem + "; give a folder (created if missing)";
      },
      "", "FOLDER");
}

void add_common_option_checks(CLI::App& app) {
  for (CLI::Option* opt : app.get_options()) {
    restate_sign_checks(*opt);
    const std::string type = opt->get_type_name();
    if (type.find("FLOAT") != std::string::npos || type.find("INT") != std::string::npos) {
      opt->check(CLI::Validator(not_empty, "", "NUMBER"));
    }
    if (type.find("FLOAT") != std::string::npos) {
      opt->check(CLI::Validator(finite_number, "", "FINITE"));
    } else if (type.find("UINT") != std::string::npos) {
      opt->check(CLI::Validator(not_negative, "", "NON-NEGATIVE"));
    }
  }
  for (CLI::App* sub : app.get_subcommands({})) add_common_option_checks(*sub);
}

}  // namespace clearshape::cli
