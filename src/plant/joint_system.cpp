#include "joint_system.hpp"

#include <string>

#include "clearshape/core/error.hpp"

namespace clearshape::plant::detail {

DriveModel::Vector initial_drive_state(const DriveModel& drive, const InitialState& init, double u0) {
  if (!init.drive_state) return drive.rest_state(u0, init.motor_angle_offset_rad);
  if (init.drive_state->size() != drive.order() || !init.drive_state->allFinite()) {
    throw_invalid("initial.drive_state.size", static_cast<double>(init.drive_state->size()),
                  std::to_string(drive.order()) + " finite values", "give the drive's full state or none");
  }
  return *init.drive_state;
}

}  // namespace clearshape::plant::detail
