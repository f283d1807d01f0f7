#include "clearshape/io/atomic_file.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <mutex>
#include <system_error>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "temp_registry.hpp"

namespace clearshape::io {

namespace fs = std::filesystem;

namespace {

// A file's identity: (device, inode), so that any path to it (relative, symlink, hard link)
// is recognised.
struct FileId {
  dev_t device = 0;
  ino_t inode = 0;
  bool operator==(const FileId&) const = default;
};

struct InputRegistry {
  std::mutex mutex;
  std::vector<std::pair<FileId, std::string>> inputs;
};
InputRegistry& registry() {
  static InputRegistry r;
  return r;
}

bool file_id(const fs::path& path, FileId& id) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return false;
  id = {st.st_dev, st.st_ino};
  return true;
}

std::atomic<unsigned long> g_temp_counter{0};

fs::path temporary_for(const fs::path& path) {
  return path.string() + fmt::format(".tmp{}-{}", static_cast<long>(::getpid()), ++g_temp_counter);
}

void create_parent(const fs::path& path) {
  const fs::path parent = path.parent_path();
  if (!parent.empty()) create_folder(parent);
}

// Writes `content` to `tmp` and flushes it to the disk; throws RuntimeError naming `target`.
void write_temporary(const fs::path& tmp, const fs::path& target, std::string_view content) {
  std::FILE* f = std::fopen(tmp.c_str(), "wb");
  if (f == nullptr) {
    throw RuntimeError(fmt::format("{}: cannot open for writing: {}", tmp.string(), std::strerror(errno)));
  }
  const bool written = std::fwrite(content.data(), 1, content.size(), f) == content.size();
  const bool flushed = std::fflush(f) == 0 && ::fsync(::fileno(f)) == 0;
  const int saved = errno;
  const bool closed = std::fclose(f) == 0;
  if (!written || !flushed || !closed) {
    std::error_code ignored;
    fs::remove(tmp, ignored);
    throw RuntimeError(fmt::format("{}: write failed: {}", target.string(), std::strerror(saved)));
  }
}

// A temporary file registered for removal by a signal while it exists.
class Temporary {
 public:
  explicit Temporary(const fs::path& target)
      : path_(temporary_for(target)), slot_(detail::register_temporary(path_.string())) {}
  ~Temporary() {
    if (!renamed_) {
      std::error_code ignored;
      fs::remove(path_, ignored);
    }
    detail::release_temporary(slot_);
  }
  Temporary(const Temporary&) = delete;
  Temporary& operator=(const Temporary&) = delete;
  const fs::path& path() const { return path_; }
  void mark_renamed() { renamed_ = true; }

 private:
  fs::path path_;
  int slot_;
  bool renamed_ = false;
};

void rename_into_place(Temporary& tmp, const fs::path& target) {
  std::error_code ec;
  fs::rename(tmp.path(), target, ec);
  if (ec) {
    throw RuntimeError(fmt::format("{}: cannot rename temporary file into place: {}", target.string(),
                                   ec.message()));
  }
  tmp.mark_renamed();
}

}  // namespace

namespace {

const char* file_kind(const fs::file_status& st) {
  switch (st.type()) {
    case fs::file_type::directory: return "a folder";
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::fifo: return "a FIFO (named pipe)";
    case fs::file_type::socket: return "a socket";
    default: return "not a regular file";
  }
}

}  // namespace

std::string folder_problem(const fs::path& folder) {
  for (fs::path p = folder; !p.empty(); p = p.parent_path()) {
    std::error_code ec;
    const fs::file_status st = fs::status(p, ec);
    if (fs::is_directory(st)) return "";
    if (fs::exists(st)) {
      const std::string kind = fs::is_regular_file(st) ? "a file" : file_kind(st);
      return p == folder ? fmt::format("{} is {}, not a folder", p.string(), kind)
                         : fmt::format("{} is {}, not a folder, so {} cannot be made in it", p.string(), kind,
                                       folder.string());
    }
    if (p == p.parent_path()) break;
  }
  return "";
}

void create_folder(const fs::path& folder) {
  if (const std::string problem = folder_problem(folder); !problem.empty()) {
    throw InvalidArgument(problem + "; give a folder (created if missing)");
  }
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw RuntimeError(fmt::format("{}: cannot create the folder: {}", folder.string(), ec.message()));
}

std::string regular_file_problem(const fs::path& path) {
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec && ec != std::errc::no_such_file_or_directory) return fmt::format("cannot be opened: {}", ec.message());
  if (!fs::exists(st)) {
    return fs::is_symlink(fs::symlink_status(path, ec)) ? "is a symbolic link to nothing" : "does not exist";
  }
  if (fs::is_regular_file(st)) return "";
  if (fs::is_directory(st)) return "is a folder, not a file";
  return fmt::format("is {}, not a regular file", file_kind(st));
}

fs::path resolve_output(const fs::path& path) {
  fs::path p = path;
  for (int hops = 0; hops < 40; ++hops) {  // the kernel's own limit on a chain of links (ELOOP)
    std::error_code ec;
    const fs::file_status st = fs::symlink_status(p, ec);
    if (ec || !fs::exists(st)) return p;  // a new file (a dangling link's target is created)
    if (fs::is_regular_file(st)) return p;
    if (fs::is_symlink(st)) {
      const fs::path target = fs::read_symlink(p, ec);
      if (ec) throw RuntimeError(fmt::format("{}: cannot read the symbolic link: {}", p.string(), ec.message()));
      p = target.is_absolute() ? target : p.parent_path() / target;
      continue;
    }
    const std::string via = p == path ? std::string() : fmt::format(" (a link to {})", p.string());
    throw InvalidArgument(fmt::format("output {}{} is {}, not a regular file; outputs are written only to regular "
                                      "files or new paths — choose another output path",
                                      path.string(), via, file_kind(st)));
  }
  throw InvalidArgument(fmt::format("output {}: more than 40 symbolic links to follow; choose another output path",
                                    path.string()));
}

bool is_input(const fs::path& path) {
  FileId id;
  if (!file_id(path, id)) return false;
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  for (const auto& [known, name] : r.inputs) {
    if (known == id) return true;
  }
  return false;
}

void note_input(const fs::path& path) {
  FileId id;
  if (!file_id(path, id)) return;
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  for (const auto& [known, name] : r.inputs) {
    if (known == id) return;
  }
  r.inputs.emplace_back(id, path.string());
}

void check_not_input(const fs::path& output) {
  FileId id;
  if (!file_id(output, id)) return;  // a new file cannot be an input
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  for (const auto& [known, name] : r.inputs) {
    if (known == id) {
      throw InvalidArgument(fmt::format(
          "output {} is the input {}; inputs are never overwritten — choose another output path",
          output.string(), name));
    }
  }
}

void clear_inputs() {
  auto& r = registry();
  std::lock_guard lock(r.mutex);
  r.inputs.clear();
}

std::string read_own_output_file(const fs::path& path) {
  // A FIFO or a device would block or never end: only regular files are read.
  if (const std::string problem = regular_file_problem(path); !problem.empty()) {
    throw InputError(path.string(), 0, "", problem);
  }
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (f == nullptr) {
    throw InputError(path.string(), 0, "", fmt::format("cannot open for reading: {}", std::strerror(errno)));
  }
  std::string text;
  char buffer[65536];
  std::size_t got = 0;
  while ((got = std::fread(buffer, 1, sizeof buffer, f)) > 0) text.append(buffer, got);
  const bool failed = std::ferror(f) != 0;
  std::fclose(f);
  if (failed) throw InputError(path.string(), 0, "", "read error");
  if (text.rfind("\xEF\xBB\xBF", 0) == 0) text.erase(0, 3);  // UTF-8 byte-order mark
  return text;
}

std::string read_text_file(const fs::path& path) {
  std::string text = read_own_output_file(path);
  note_input(path);
  return text;
}

void write_text_atomic(const fs::path& path, std::string_view content) {
  check_not_input(path);
  const fs::path target = resolve_output(path);
  create_parent(target);
  Temporary tmp(target);
  write_temporary(tmp.path(), path, content);
  rename_into_place(tmp, target);
}

AtomicBatch::~AtomicBatch() = default;

void AtomicBatch::add(const fs::path& path, std::string content) {
  check_not_input(path);
  const fs::path target = fs::weakly_canonical(fs::absolute(resolve_output(path)));
  for (const auto& [known, text] : files_) {
    if (fs::weakly_canonical(fs::absolute(resolve_output(known))) == target) {
      throw InvalidArgument(fmt::format(
          "two outputs name the same file {}; give them different paths", path.string()));
    }
  }
  files_.emplace_back(path, std::move(content));
}

void AtomicBatch::commit() {
  std::vector<std::unique_ptr<Temporary>> temps;
  std::vector<fs::path> targets;
  for (const auto& [path, content] : files_) {
    check_not_input(path);
    targets.push_back(resolve_output(path));
    create_parent(targets.back());
    temps.push_back(std::make_unique<Temporary>(targets.back()));
    write_temporary(temps.back()->path(), path, content);
  }
  for (std::size_t i = 0; i < files_.size(); ++i) rename_into_place(*temps[i], targets[i]);
  files_.clear();
}

bool is_temporary_name(std::string_view name) noexcept {
  const auto at = name.rfind(".tmp");
  if (at == std::string_view::npos || at == 0) return false;
  std::string_view rest = name.substr(at + 4);
  if (rest.empty()) return false;
  bool dash = false;
  bool digit_before = false;
  for (char c : rest) {
    if (c == '-' && !dash && digit_before) {
      dash = true;
      digit_before = false;
    } else if (c >= '0' && c <= '9') {
      digit_before = true;
    } else {
      return false;
    }
  }
  return digit_before;
}

std::size_t remove_stale_temporaries(const fs::path& folder) {
  std::error_code ec;
  std::size_t removed = 0;
  for (const auto& entry : fs::directory_iterator(folder, ec)) {
    if (entry.is_regular_file(ec) && is_temporary_name(entry.path().filename().string())) {
      if (fs::remove(entry.path(), ec)) ++removed;
    }
  }
  return removed;
}

}  // namespace clearshape::io
