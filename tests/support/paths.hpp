#pragma once
// Where tests find their data: committed golden files and ../shared (third-party data).
#include <filesystem>
#include <string>

namespace clearshape::testing {

inline std::filesystem::path golden_path(const std::string& name) {
  return std::filesystem::path(CLEARSHAPE_GOLDEN_DIR) / name;
}
inline std::filesystem::path shared_path(const std::string& name) {
  return std::filesystem::path(CLEARSHAPE_SHARED_DIR) / name;
}

}  // namespace clearshape::testing
