#pragma once
// The built-in truths of the simulated rig, by name (`--rig NAME` in `clearshape simulate` and
// `clearshape study`, `rig = "NAME"` in a study protocol):
//   thesis      the calibrated thesis rig (truth.hpp; the default)
//   large-play  the thesis's drive and sensors with a 1° steel-pin joint (large_play.hpp)
#include <array>
#include <string_view>

#include "clearshape/rig/truth.hpp"

namespace clearshape::rig {

inline constexpr std::array<std::string_view, 2> kBuiltinTruthNames = {"thesis", "large-play"};

bool is_builtin_truth(std::string_view name) noexcept;
/// The truth of a name. Throws InvalidArgument naming `option` and the allowed names.
RigTruth builtin_truth(std::string_view name, std::string_view option = "rig");

}  // namespace clearshape::rig
