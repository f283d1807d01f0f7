#include "command.hpp"

#include <cstdio>
#include <utility>

namespace clearshape::cli {

std::vector<Command>& registered_commands() {
  static std::vector<Command> commands;
  return commands;
}

bool register_command(Command command) {
  registered_commands().push_back(std::move(command));
  return true;
}

void print_json(const nlohmann::ordered_json& document) {
  const std::string text = document.dump(2);
  std::fwrite(text.data(), 1, text.size(), stdout);
  std::fputc('\n', stdout);
}

}  // namespace clearshape::cli
