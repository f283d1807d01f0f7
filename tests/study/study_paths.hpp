#pragma once
// Where the study tests find the committed protocols (studies/ at the repository root).
#include <filesystem>

#include "support/paths.hpp"

namespace clearshape::testing {

inline std::filesystem::path studies_path(const std::string& name) {
  return golden_path("").parent_path().parent_path().parent_path() / "studies" / name;
}

}  // namespace clearshape::testing
