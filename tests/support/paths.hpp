#pragma once
// Where tests find their data (committed golden files, the protocols in studies/, third-party
// data in the shared folder) and where they write (per-process temporary folders).
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <utility>

#include <unistd.h>

namespace clearshape::testing {

inline std::filesystem::path golden_path(const std::string& name) {
  return std::filesystem::path(CLEARSHAPE_GOLDEN_DIR) / name;
}
inline std::filesystem::path shared_path(const std::string& name) {
  return std::filesystem::path(CLEARSHAPE_SHARED_DIR) / name;
}
/// The committed study protocols (studies/ at the repository root).
inline std::filesystem::path studies_path(const std::string& name) {
  return golden_path("").parent_path().parent_path().parent_path() / "studies" / name;
}
/// `<tmp>/<name>_<pid>`: per process, so several test processes (and build trees) may run at once.
inline std::filesystem::path process_temp_path(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}
/// process_temp_path(name), emptied (not created: the code under test makes it).
inline std::filesystem::path emptied_temp_path(const std::string& name) {
  const auto dir = process_temp_path(name);
  std::filesystem::remove_all(dir);
  return dir;
}
/// process_temp_path(name), emptied and created.
inline std::filesystem::path fresh_temp_dir(const std::string& name) {
  const auto dir = process_temp_path(name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}
/// A file's bytes ("" when it cannot be read). Streamed through rdbuf(), not built from
/// istreambuf_iterators: GCC 12 at -O2 reports a false -Wnull-dereference inside libstdc++'s
/// streambuf for `std::string(std::istreambuf_iterator<char>(in), {})`.
inline std::string read_bytes(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream bytes;
  if (in) bytes << in.rdbuf();
  return std::move(bytes).str();
}

}  // namespace clearshape::testing
