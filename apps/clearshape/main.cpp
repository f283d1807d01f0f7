// clearshape: input shaping for servo-driven joints with clearance.
// Exit codes (DESIGN.md §4): 0 ok, 1 run-time failure, 2 bad usage or bad input.
#include <algorithm>
#include <cstdio>
#include <exception>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/version.hpp"
#include "command.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "clearshape: identify a servo joint with clearance, design input shapers and prove the "
      "reduction of residual vibration (after Gunduzalp 2015)."};
  app.set_version_flag("--version", std::string("clearshape ") + clearshape::kVersion);
  app.require_subcommand(1);
  app.fallthrough(false);

  auto& commands = clearshape::cli::registered_commands();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const auto& a, const auto& b) { return a.order < b.order; });
  for (const auto& command : commands) {
    CLI::App* sub = app.add_subcommand(command.name, command.description);
    command.setup(*sub);
  }

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  } catch (const clearshape::InvalidArgument& e) {
    fmt::print(stderr, "clearshape: error: {}\n", e.what());
    return 2;
  } catch (const clearshape::InputError& e) {
    fmt::print(stderr, "clearshape: error: {}\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    fmt::print(stderr, "clearshape: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "clearshape: failed: {}\n", e.what());
    return 1;
  }
  std::fflush(stdout);
  return 0;
}
