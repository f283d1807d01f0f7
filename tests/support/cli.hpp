#pragma once
// Runs the clearshape executable in a test and captures exit code, stdout and stderr.
#include <string>

namespace clearshape::testing {

struct CliResult {
  int exit_code = -1;
  std::string out;
  std::string err;
};

/// Runs `clearshape <arguments>` through /bin/sh (arguments are not escaped: quote them).
CliResult run_cli(const std::string& arguments);
/// Runs any shell command the same way (stdout and stderr apart).
CliResult run_shell(const std::string& command);

}  // namespace clearshape::testing
