#pragma once
// The command-signal options shared by `clearshape signal` and `clearshape simulate`: one flag
// per parameter of clearshape/signal/parameters.hpp, checked against the chosen signal type.
#include <string>
#include <string_view>
#include <vector>

#include <CLI/CLI.hpp>

#include "clearshape/signal/signal.hpp"

namespace clearshape::cli {

class SignalOptions {
 public:
  /// Adds --amplitude, --start-s, …, --rise-shape, --levels and --repeat to `sub`. `type_flag`
  /// is the option that names the signal type (for error messages, e.g. "--type").
  /// The object must outlive the parse (CLI11 writes into it).
  void add_to(CLI::App& sub, std::string type_flag);
  /// The signal `type` from the options given. An option the type does not take, or a bad
  /// value, throws InvalidArgument naming the command-line option (and the ones it takes).
  signal::Signal build(const std::string& type) const;

  /// "step|ramp|…" for help text, and the CLI11 check that accepts exactly those names.
  static std::string type_list();
  static CLI::IsMember type_check();

 private:
  std::string type_flag_;
  std::vector<double> numbers_;
  std::vector<CLI::Option*> number_options_;
  std::string rise_shape_;
  CLI::Option* rise_shape_option_ = nullptr;
  std::string levels_;
  CLI::Option* levels_option_ = nullptr;
  bool repeat_ = false;
  CLI::Option* repeat_option_ = nullptr;
  std::string sweep_;
  CLI::Option* sweep_option_ = nullptr;
};

/// "1, 2,3" → {1, 2, 3}; anything else throws InvalidArgument naming `option` and the item.
std::vector<double> parse_levels(const std::string& text, std::string_view option = "--levels");

}  // namespace clearshape::cli
