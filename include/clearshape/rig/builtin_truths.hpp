#pragma once
// The built-in truths of the simulated rig, by name (`--rig NAME` in `clearshape simulate` and
// `clearshape study`, `rig = "NAME"` in a study protocol):
//   thesis      the calibrated thesis rig (truth.hpp; the default)
//   large-play  the thesis's drive and sensors with a 1° steel-pin joint (large_play.hpp)
//   worn-coupling  the calibrated thesis rig with 1° of play and a 0.01 N·m bearing Coulomb
//               torque (worn_coupling.hpp)
#include <array>
#include <string_view>

#include "clearshape/rig/truth.hpp"

namespace clearshape::rig {

inline constexpr std::array<std::string_view, 3> kBuiltinTruthNames = {"thesis", "large-play", "worn-coupling"};

bool is_builtin_truth(std::string_view name) noexcept;
/// The truth of a name. Throws InvalidArgument naming `option` and the allowed names.
RigTruth builtin_truth(std::string_view name, std::string_view option = "rig");

}  // namespace clearshape::rig
