#include "shared_fixture.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <system_error>

#include "paths.hpp"

namespace clearshape::testing {

namespace fs = std::filesystem;

namespace {

// An exclusive flock(2) held for the object's life (released by close on every path).
class FileLock {
 public:
  explicit FileLock(const fs::path& path) : fd_(::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644)) {
    if (fd_ < 0 || ::flock(fd_, LOCK_EX) != 0) throw std::runtime_error("shared fixture: cannot lock " + path.string());
  }
  ~FileLock() { ::close(fd_); }
  FileLock(const FileLock&) = delete;
  FileLock& operator=(const FileLock&) = delete;

 private:
  int fd_;
};

void add_entry(std::ostringstream& key, const fs::path& p) {
  std::error_code ec;
  const auto size = fs::is_regular_file(p, ec) ? fs::file_size(p, ec) : 0;
  const auto time = fs::last_write_time(p, ec).time_since_epoch().count();
  key << p.string() << ' ' << size << ' ' << time << '\n';
}

}  // namespace

std::string files_key(const std::vector<fs::path>& files) {
  std::ostringstream key;
  for (const fs::path& f : files) {
    add_entry(key, f);
    std::error_code ec;
    if (!fs::is_directory(f, ec)) continue;
    for (const auto& e : fs::recursive_directory_iterator(f, fs::directory_options::skip_permission_denied, ec)) {
      if (e.path().filename() != "__pycache__" && e.path().string().find("__pycache__") == std::string::npos) {
        add_entry(key, e.path());
      }
    }
  }
  return key.str();
}

fs::path shared_fixture(const std::string& name, const std::string& key,
                        const std::function<bool(const fs::path&)>& build) {
  const fs::path cache = fs::path(CLEARSHAPE_TEST_CACHE_DIR);
  fs::create_directories(cache);
  const FileLock lock(cache / (name + ".lock"));
  const fs::path folder = cache / name;
  const fs::path key_file = cache / (name + ".key");
  if (fs::is_directory(folder) && read_bytes(key_file) == key) return folder;
  fs::remove_all(folder);
  fs::remove(key_file);
  const fs::path scratch = cache / (name + ".incomplete");
  fs::remove_all(scratch);
  fs::create_directories(scratch);
  if (!build(scratch)) {
    fs::remove_all(scratch);
    return {};
  }
  fs::rename(scratch, folder);
  std::ofstream(key_file, std::ios::binary) << key;  // written last: a folder without it is rebuilt
  return folder;
}

}  // namespace clearshape::testing
