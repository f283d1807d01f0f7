#pragma once
// The arm a Python arm function works on (bind_arm.cpp, bind_arm_modes.cpp): a built-in arm by
// name, or one's own from URDF and TOML texts.
#include <optional>
#include <string>

#include <pybind11/pybind11.h>

#include "clearshape/arm/arm.hpp"

namespace clearshape::python {

/// The built-in arm `name`, or the arm of the texts `urdf` + `toml` (both or neither:
/// InvalidArgument otherwise).
arm::ArmModel arm_model_of(const std::string& name, const std::optional<std::string>& urdf,
                           const std::optional<std::string>& toml);

/// arm_mode_map (bind_arm_modes.cpp), registered by bind_arm.
void bind_arm_mode_map(pybind11::module_& m);

}  // namespace clearshape::python
