#pragma once
// Subcommand registry of the clearshape CLI. Each cmd_*.cpp registers its subcommand from a
// static initializer, so adding a subcommand touches no other file:
//
//   static const bool registered = clearshape::cli::register_command(
//       {"shape", "Design an input shaper", 10, [](CLI::App& sub) { ... sub.callback(...); }});
//
// Callbacks report bad usage or input by throwing clearshape::InvalidArgument / InputError
// (exit 2) and run-time failures by throwing RuntimeError (exit 1). Results go to stdout,
// progress and logs to stderr.
#include <functional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

namespace clearshape::cli {

struct Command {
  std::string name;
  std::string description;
  int order = 100;  ///< position in --help
  std::function<void(CLI::App&)> setup;
};

bool register_command(Command command);
std::vector<Command>& registered_commands();

/// Prints a JSON document (pretty, 2 spaces) on stdout.
void print_json(const nlohmann::ordered_json& document);

}  // namespace clearshape::cli
