#include "clearshape/rig/types.hpp"

#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/rig/rig.hpp"

namespace clearshape::rig {

std::string_view to_string(CommandMode mode) noexcept {
  switch (mode) {
    case CommandMode::position: return "position";
    case CommandMode::speed: return "speed";
  }
  return "unknown";
}

CommandMode command_mode_from_string(std::string_view name) {
  if (name == "position") return CommandMode::position;
  if (name == "speed") return CommandMode::speed;
  throw InvalidArgument("mode = '" + std::string(name) +
                        "' is not a drive mode; allowed: position, speed");
}

std::string_view to_string(LifecycleState state) noexcept {
  switch (state) {
    case LifecycleState::unconfigured: return "unconfigured";
    case LifecycleState::inactive: return "inactive";
    case LifecycleState::active: return "active";
    case LifecycleState::error: return "error";
  }
  return "unknown";
}

}  // namespace clearshape::rig
