// clearshape: input shaping for servo-driven joints with clearance.
// Exit codes (docs/cli.md): 0 ok, 1 run-time failure (including a failed write to stdout),
// 2 bad usage or bad input.
#include <algorithm>
#include <cstdio>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>
#include <glog/logging.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/version.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "command.hpp"
#include "option_checks.hpp"

namespace {

// Ceres logs through glog; its messages are internal detail, shown only with --verbose.
void route_library_logging(const char* argv0, bool verbose) {
  FLAGS_logtostderr = true;
  FLAGS_minloglevel = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
  FLAGS_stderrthreshold = verbose ? google::GLOG_INFO : google::GLOG_FATAL;
  google::InitGoogleLogging(argv0);
}

// --verbose may stand anywhere on the line; it is taken out before CLI11 parses the rest.
bool take_verbose(int& argc, char** argv) {
  bool verbose = false;
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--verbose") == 0) {
      verbose = true;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  return verbose;
}

// `clearshape bogus` names the unknown subcommand and lists the known ones.
int unknown_subcommand(const CLI::App& app, const char* word) {
  std::string known;
  for (const CLI::App* sub : app.get_subcommands({})) known += (known.empty() ? "" : ", ") + sub->get_name();
  fmt::print(stderr, "clearshape: error: unknown subcommand '{}'; subcommands: {} (clearshape --help)\n",
             word, known);
  return 2;
}

// Output that could not be written is a failure, never a silent success.
int check_stdout(int code) {
  std::cout.flush();
  const bool failed = std::fflush(stdout) != 0 || std::ferror(stdout) != 0 || !std::cout;
  if (failed && code == 0) {
    fmt::print(stderr, "clearshape: failed: cannot write to standard output: {}\n", std::strerror(errno));
    return 1;
  }
  return code;
}

int run(CLI::App& app, int argc, char** argv) {
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
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  clearshape::io::install_signal_cleanup();
  route_library_logging(argv[0], take_verbose(argc, argv));

  CLI::App app{
      "clearshape: identify a servo joint with clearance, design input shapers and prove the "
      "reduction of residual vibration (after Gunduzalp 2015)."};
  app.set_version_flag("--version", std::string("clearshape ") + clearshape::kVersion);
  app.add_flag("--verbose")->description(
      "Show the numerical libraries' own log messages (Ceres) on stderr");
  app.require_subcommand(1);
  app.fallthrough(false);

  auto& commands = clearshape::cli::registered_commands();
  std::stable_sort(commands.begin(), commands.end(),
                   [](const auto& a, const auto& b) { return a.order < b.order; });
  for (const auto& command : commands) {
    CLI::App* sub = app.add_subcommand(command.name, command.description);
    command.setup(*sub);
  }
  clearshape::cli::add_common_option_checks(app);

  const auto is_subcommand = [&app](const char* word) {
    const auto subs = app.get_subcommands({});
    return std::any_of(subs.begin(), subs.end(), [word](const CLI::App* sub) { return sub->check_name(word); });
  };
  if (argc > 1 && argv[1][0] != '-' && !is_subcommand(argv[1])) {
    return unknown_subcommand(app, argv[1]);
  }
  return check_stdout(run(app, argc, argv));
}
