#include "support/cli.hpp"

#include <sys/wait.h>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <unistd.h>

namespace clearshape::testing {

CliResult run_cli(const std::string& arguments) { return run_shell(std::string(CLEARSHAPE_CLI) + " " + arguments); }

CliResult run_shell(const std::string& shell_command) {
  namespace fs = std::filesystem;
  static int counter = 0;
  const fs::path err_file = fs::temp_directory_path() /
                            ("clearshape_cli_err_" + std::to_string(::getpid()) + "_" + std::to_string(counter++));
  const std::string command = shell_command + " 2>" + err_file.string();
  CliResult result;
  FILE* pipe = ::popen(command.c_str(), "r");
  if (pipe == nullptr) return result;
  std::array<char, 4096> buffer{};
  std::size_t n = 0;
  while ((n = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) result.out.append(buffer.data(), n);
  const int status = ::pclose(pipe);
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(err_file);
  std::stringstream ss;
  ss << in.rdbuf();
  result.err = ss.str();
  std::error_code ec;
  fs::remove(err_file, ec);
  return result;
}

}  // namespace clearshape::testing
