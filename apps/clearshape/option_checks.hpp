#pragma once
// One option-validation layer for every subcommand, applied by main() after the subcommands
// have declared their options (so a new cmd_*.cpp gets it without doing anything):
//   - a floating-point option rejects NaN and ±inf ("--spread-weight: nan is not a finite number");
//   - an unsigned option rejects a negative value instead of letting it wrap
//     ("--noise-seed: -1 is negative; allowed: 0 … 18446744073709551615").
// CLI11 runs these checks while parsing, before any subcommand callback, and its message names
// the option as the user typed it. Range checks specific to an option stay with the option.
#include <string>

#include <CLI/CLI.hpp>

namespace clearshape::cli {

/// Adds the checks to every option of `app` and, recursively, of its subcommands.
void add_common_option_checks(CLI::App& app);

/// For an option that is off unless given (e.g. --grid-hz): a value in (0, max], else
/// "--grid-hz: 0 is out of range; allowed: (0, 1e+06] Hz (omit --grid-hz for none)".
CLI::Validator positive_at_most(double max, const std::string& unit, const std::string& option);

/// For an output-folder option (--out): the folder, or its nearest existing parent, must be a
/// folder — "--out: out is a file, not a folder; give a folder (created if missing)" — checked
/// while parsing, before any work (it was a raw "Not a directory" after the work, exit 1).
CLI::Validator output_folder();

}  // namespace clearshape::cli
