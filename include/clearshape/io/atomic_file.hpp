#pragma once
// Safe files: what clearshape reads is never overwritten, what it writes appears whole or not at
// all, and what it leaves behind on failure or on SIGINT/SIGTERM is only what was there before.
//
//   const std::string text = io::read_text_file("run.csv");   // registered as an input, BOM dropped
//   io::write_text_atomic("out.csv", csv);                     // refuses "run.csv"; temp + rename
//
//   io::AtomicBatch batch;                                     // several files, committed together
//   batch.add("run.csv", csv);
//   batch.add("run.json", sidecar);                            // same target twice: refused
//   batch.commit();                                            // every temp written, then renamed
//
// Temporary files are named `<target>.tmp<pid>-<n>` beside their target; `is_temporary_name`
// recognises that pattern so a resumed job can remove stale ones it left (and nothing else).
// `install_signal_cleanup()` (called once by the CLI) removes the temporary files in flight when
// SIGINT or SIGTERM arrives, then lets the signal end the process as it would have.
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace clearshape::io {

/// Reads a whole file as text: registers it as an input (see note_input), drops a leading
/// UTF-8 byte-order mark (the one BOM rule of every reader). Throws InputError naming the path
/// when it does not exist, is a folder or cannot be read.
std::string read_text_file(const std::filesystem::path& path);
/// The same for a file this process's job wrote itself and may write again (a resumable study
/// reading back its own runs, sidecars and manifest): read, BOM dropped, NOT registered as an
/// input — otherwise a rerun after a protocol change could not replace its own stale run.
std::string read_own_output_file(const std::filesystem::path& path);

/// Registers `path` as an input of this process: no output may resolve to it afterwards.
void note_input(const std::filesystem::path& path);
/// Throws InvalidArgument when `output` resolves to a registered input (same file, through any
/// relative path, link or hard link), naming both.
void check_not_input(const std::filesystem::path& output);
/// True when `path` resolves to a registered input (a cleaner must leave it alone).
bool is_input(const std::filesystem::path& path);
/// Where an output to `path` is written: `path` itself, or the file a chain of symbolic links
/// ends at (the link is kept, its target replaced). Throws InvalidArgument naming the path when
/// that file exists and is not a regular file (a folder, a device such as /dev/null, a FIFO, a
/// socket): an output never replaces one.
std::filesystem::path resolve_output(const std::filesystem::path& path);
/// Why `path` (links followed) is not a regular file to read — "does not exist", "is a folder,
/// not a file", "is a FIFO (named pipe), not a regular file", "cannot be opened: Too many levels
/// of symbolic links", … — or "" when it is one.
std::string regular_file_problem(const std::filesystem::path& path);
/// Why `folder` cannot be an output folder — "out is a file, not a folder", "a is a file, not a
/// folder, so a/b cannot be made in it" (the nearest existing parent, links followed) — or "".
std::string folder_problem(const std::filesystem::path& folder);
/// Creates `folder` and its missing parents. Throws InvalidArgument naming the path when it or a
/// parent is not a folder (folder_problem), RuntimeError naming it for any other failure.
void create_folder(const std::filesystem::path& folder);
/// Forgets every registered input (tests; a long-lived process between jobs).
void clear_inputs();

/// Writes `content` to `path` atomically (through resolve_output: a symbolic link's target is
/// replaced, a non-regular file refused). Creates missing parent folders (create_folder: a
/// parent that is a file is InvalidArgument, named). Refuses an input.
/// Throws clearshape::RuntimeError naming the path on failure (the old file is then untouched).
void write_text_atomic(const std::filesystem::path& path, std::string_view content);

/// Several files that appear together or not at all: every file is written to its temporary
/// first; only when all succeeded are they renamed into place, in the order added.
class AtomicBatch {
 public:
  AtomicBatch() = default;
  AtomicBatch(const AtomicBatch&) = delete;
  AtomicBatch& operator=(const AtomicBatch&) = delete;
  ~AtomicBatch();
  /// Throws InvalidArgument when `path` is an input or was already added (two outputs, one file).
  void add(const std::filesystem::path& path, std::string content);
  /// Writes and renames; on failure removes every temporary and throws RuntimeError
  /// (InvalidArgument when a target's folder lies under a file: folder_problem).
  void commit();

 private:
  std::vector<std::pair<std::filesystem::path, std::string>> files_;
};

/// True for a name this layer gives its temporary files (`<name>.tmp<digits>[-<digits>]`).
bool is_temporary_name(std::string_view filename) noexcept;
/// Removes the temporary files this layer left in `folder` (not recursive); returns how many.
std::size_t remove_stale_temporaries(const std::filesystem::path& folder);

/// Installs SIGINT/SIGTERM handlers that unlink the temporary files in flight, then re-raise.
void install_signal_cleanup();

}  // namespace clearshape::io
