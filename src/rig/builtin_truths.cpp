#include "clearshape/rig/builtin_truths.hpp"

#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/rig/large_play.hpp"
#include "clearshape/rig/worn_coupling.hpp"

namespace clearshape::rig {

bool is_builtin_truth(std::string_view name) noexcept {
  for (const auto n : kBuiltinTruthNames) {
    if (n == name) return true;
  }
  return false;
}

RigTruth builtin_truth(std::string_view name, std::string_view option) {
  if (name == "thesis") return thesis_rig_truth();
  if (name == "large-play") return large_play_rig_truth();
  if (name == "worn-coupling") return worn_coupling_rig_truth();
  std::string allowed;
  for (const auto n : kBuiltinTruthNames) allowed += (allowed.empty() ? "" : ", ") + std::string(n);
  throw InvalidArgument(std::string(option) + " = '" + std::string(name) + "' is not a built-in rig; allowed: " +
                        allowed);
}

}  // namespace clearshape::rig
