// The safe-file layer: inputs are never outputs, a batch appears whole or not at all, temporary
// names are recognised (and only they are), one BOM rule.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/interrupt.hpp"
#include "../../src/io/temp_registry.hpp"  // the fixed table the handler walks (internal)
#include "clearshape/io/table.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
namespace io = clearshape::io;

namespace {
fs::path temp_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("clearshape_atomic_" + name + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}
void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
std::string read(const fs::path& p) { return clearshape::testing::read_bytes(p); }
}  // namespace

TEST(AtomicFile, AnInputIsNeverAnOutputThroughAnyPath) {
  io::clear_inputs();
  const fs::path dir = temp_dir("input");
  write(dir / "in.csv", "time_s,x\n0,1\n1,2\n");
  (void)io::read_table(dir / "in.csv");
  fs::create_symlink(dir / "in.csv", dir / "link.csv");
  fs::create_hard_link(dir / "in.csv", dir / "hard.csv");
  for (const auto& out : {dir / "in.csv", dir / "." / "in.csv", dir / "link.csv", dir / "hard.csv"}) {
    EXPECT_THROW(io::write_text_atomic(out, "overwritten"), clearshape::InvalidArgument) << out;
  }
  EXPECT_EQ(read(dir / "in.csv"), "time_s,x\n0,1\n1,2\n");
  io::write_text_atomic(dir / "other.csv", "fine");
  EXPECT_EQ(read(dir / "other.csv"), "fine");
  io::clear_inputs();
}

TEST(AtomicFile, BatchRefusesTwoOutputsWithOneNameAndWritesNothing) {
  const fs::path dir = temp_dir("batch");
  io::AtomicBatch batch;
  batch.add(dir / "run.json", "csv");
  EXPECT_THROW(batch.add(dir / "sub" / ".." / "run.json", "sidecar"), clearshape::InvalidArgument);
  EXPECT_FALSE(fs::exists(dir / "run.json"));
}

TEST(AtomicFile, BatchThatFailsLeavesTheOldFilesAndNoTemporaries) {
  const fs::path dir = temp_dir("fail");
  write(dir / "a.csv", "old a");
  write(dir / "blocker", "a file where b.csv's folder must go");
  io::AtomicBatch batch;
  batch.add(dir / "a.csv", "new a");            // its temporary is written first …
  batch.add(dir / "blocker" / "b.csv", "new b");  // … then b's folder cannot be made
  // A file where a folder must go is bad usage (exit 2), named — not a raw "Not a directory".
  try {
    batch.commit();
    ADD_FAILURE() << "commit() wrote under a file";
  } catch (const clearshape::InvalidArgument& e) {
    EXPECT_EQ(std::string(e.what()), (dir / "blocker").string() + " is a file, not a folder; give a folder (created if missing)");
  }
  EXPECT_EQ(read(dir / "a.csv"), "old a");  // renamed only after every write succeeded
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_FALSE(io::is_temporary_name(e.path().filename().string())) << e.path();
  }
}

// The nearest existing parent decides: a folder (any depth to create below it) or not.
TEST(AtomicFile, FolderProblemNamesTheParentThatIsNoFolder) {
  const fs::path dir = temp_dir("folders");
  write(dir / "file", "x");
  EXPECT_EQ(io::folder_problem(dir), "");
  EXPECT_EQ(io::folder_problem(dir / "new" / "deeper"), "");
  EXPECT_EQ(io::folder_problem(dir / "file"), (dir / "file").string() + " is a file, not a folder");
  EXPECT_EQ(io::folder_problem(dir / "file" / "a" / "b"),
            (dir / "file").string() + " is a file, not a folder, so " + (dir / "file" / "a" / "b").string() +
                " cannot be made in it");
  EXPECT_EQ(io::folder_problem("/dev/null/out"), "/dev/null is a character device, not a folder, so /dev/null/out "
                                                 "cannot be made in it");
  EXPECT_THROW(io::create_folder(dir / "file" / "a"), clearshape::InvalidArgument);
  io::create_folder(dir / "new" / "deeper");
  EXPECT_TRUE(fs::is_directory(dir / "new" / "deeper"));
}

TEST(AtomicFile, TemporaryNamesAreRecognisedAndOnlyThey) {
  EXPECT_TRUE(io::is_temporary_name("run.csv.tmp1234"));
  EXPECT_TRUE(io::is_temporary_name("run.csv.tmp1234-7"));
  EXPECT_FALSE(io::is_temporary_name("run.csv"));
  EXPECT_FALSE(io::is_temporary_name("notes.tmp"));
  EXPECT_FALSE(io::is_temporary_name("my.tmp12.csv"));
  EXPECT_FALSE(io::is_temporary_name("x.tmp12-"));
  const fs::path dir = temp_dir("stale");
  write(dir / "run.csv.tmp99-1", "half");
  write(dir / "mine.tmp", "user");
  EXPECT_EQ(io::remove_stale_temporaries(dir), 1u);
  EXPECT_TRUE(fs::exists(dir / "mine.tmp"));
}

TEST(AtomicFile, ReadTextFileDropsOneByteOrderMarkAndNamesFolders) {
  const fs::path dir = temp_dir("bom");
  write(dir / "bom.csv", "\xEF\xBB\xBFtime_s,x\n0,1\n1,2\n");
  EXPECT_EQ(io::read_text_file(dir / "bom.csv").substr(0, 6), "time_s");
  EXPECT_EQ(io::read_table(dir / "bom.csv").names.front(), "time_s");
  EXPECT_EQ(io::parse_table("\xEF\xBB\xBFtime_s,x\n0,1\n", "text").names.front(), "time_s");
  try {
    (void)io::read_text_file(dir);
    FAIL() << "a folder was read as a file";
  } catch (const clearshape::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("folder"), std::string::npos) << e.what();
  }
  io::clear_inputs();
}

// Issue 21 item 2: an output that is a symbolic link replaces the link's target (the link stays);
// one that is a FIFO, a character device or a folder is refused by name and left as it was.
TEST(AtomicFile, AnOutputFollowsItsLinkAndNeverReplacesANonRegularFile) {
  const fs::path dir = temp_dir("special");
  write(dir / "target.csv", "old");
  fs::create_symlink("target.csv", dir / "link.csv");
  io::write_text_atomic(dir / "link.csv", "new");
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.csv")));
  EXPECT_EQ(read(dir / "target.csv"), "new");
  {
    io::AtomicBatch batch;  // the batch resolves the same way
    batch.add(dir / "link.csv", "newer");
    EXPECT_THROW(batch.add(dir / "target.csv", "twice"), clearshape::InvalidArgument);  // one file, two names
    batch.commit();
  }
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(dir / "link.csv")));
  EXPECT_EQ(read(dir / "target.csv"), "newer");

  ASSERT_EQ(::mkfifo((dir / "fifo").c_str(), 0600), 0);
  fs::create_symlink(dir / "fifo", dir / "to_fifo");
  fs::create_directories(dir / "folder");
  std::vector<fs::path> refused = {dir / "fifo", dir / "to_fifo", dir / "folder"};
  const bool device = ::mknod((dir / "null").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0;  // needs root
  if (device) refused.push_back(dir / "null");
  for (const fs::path& out : refused) {
    try {
      io::write_text_atomic(out, "data");
      ADD_FAILURE() << out << " was written";
    } catch (const clearshape::InvalidArgument& e) {
      EXPECT_NE(std::string(e.what()).find(out.string()), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("not a regular file"), std::string::npos) << e.what();
    }
    io::AtomicBatch batch;
    EXPECT_THROW(batch.add(out, "data"), clearshape::InvalidArgument) << out;
  }
  EXPECT_TRUE(fs::is_fifo(dir / "fifo"));
  EXPECT_TRUE(fs::is_directory(dir / "folder"));
  if (device) {
    EXPECT_TRUE(fs::is_character_file(dir / "null"));
  }
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_FALSE(io::is_temporary_name(e.path().filename().string())) << e.path();
  }
  EXPECT_EQ(io::regular_file_problem(dir / "fifo"), "is a FIFO (named pipe), not a regular file");
  EXPECT_EQ(io::regular_file_problem(dir / "folder"), "is a folder, not a file");
  EXPECT_EQ(io::regular_file_problem(dir / "none"), "does not exist");
  EXPECT_EQ(io::regular_file_problem(dir / "target.csv"), "");
  fs::create_symlink("loop_b", dir / "loop_a");
  fs::create_symlink("loop_a", dir / "loop_b");
  EXPECT_NE(io::regular_file_problem(dir / "loop_a").find("symbolic links"), std::string::npos)
      << io::regular_file_problem(dir / "loop_a");
  // Reading a FIFO would block for ever: it is refused by name instead.
  EXPECT_THROW((void)io::read_text_file(dir / "fifo"), clearshape::InputError);
  fs::remove_all(dir);
}

TEST(AtomicFile, IsInputSeesEveryPathToARegisteredInput) {
  io::clear_inputs();
  const fs::path dir = temp_dir("is_input");
  write(dir / "in.csv", "x");
  fs::create_symlink(dir / "in.csv", dir / "link.csv");
  EXPECT_FALSE(io::is_input(dir / "in.csv"));
  io::note_input(dir / "in.csv");
  EXPECT_TRUE(io::is_input(dir / "link.csv"));
  EXPECT_TRUE(io::is_input(dir / "." / "in.csv"));
  EXPECT_FALSE(io::is_input(dir / "absent.csv"));
  io::clear_inputs();
  fs::remove_all(dir);
}

// SIGINT inside a DeferredInterrupts scope is recorded, not fatal; end_process_if_interrupted
// then removes the temporaries in flight and ends the process by that signal (run in a child).
TEST(DeferredInterrupts, ASignalIsRecordedThenEndsTheProcessWhenAsked) {
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    io::DeferredInterrupts scope;
    if (io::interrupt_requested().load()) ::_exit(10);
    ::raise(SIGINT);
    if (!io::interrupt_requested().load() || io::pending_interrupt() != SIGINT) ::_exit(11);
    ::raise(SIGTERM);  // the first signal is the one that ends the process
    if (io::pending_interrupt() != SIGINT) ::_exit(12);
    scope.end_process_if_interrupted();
    ::_exit(13);  // not reached
  }
  int status = 0;
  ASSERT_EQ(::waitpid(child, &status, 0), child);
  ASSERT_TRUE(WIFSIGNALED(status)) << "exit code " << (WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  EXPECT_EQ(WTERMSIG(status), SIGINT);
  // Outside a scope nothing is pending and the flag is clear.
  EXPECT_EQ(io::pending_interrupt(), 0);
  EXPECT_FALSE(io::interrupt_requested().load());
  {
    io::DeferredInterrupts scope;
    EXPECT_THROW(io::DeferredInterrupts nested, clearshape::RuntimeError);
    scope.end_process_if_interrupted();  // nothing recorded: returns
  }
}

// The exit-code list: SIGHUP (a closed terminal) and SIGPIPE (a closed pipe) left the temporary
// files in flight behind (100 MB of them in the audit). The cleanup handler now takes them as it
// takes SIGINT and SIGTERM: the temporary is removed and the signal still ends the process.
TEST(AtomicFile, EveryTerminatingSignalRemovesTheTemporariesInFlight) {
  const fs::path dir = temp_dir("signals");
  for (const int signo : {SIGINT, SIGTERM, SIGHUP, SIGPIPE}) {
    const fs::path tmp = dir / ("out.csv.tmp" + std::to_string(::getpid()) + "-" + std::to_string(signo));
    const pid_t child = ::fork();
    ASSERT_GE(child, 0);
    if (child == 0) {
      io::install_signal_cleanup();
      std::ofstream(tmp) << "half written";
      if (io::detail::register_temporary(tmp.string()) < 0) ::_exit(10);
      ::raise(signo);
      ::_exit(11);  // not reached: the signal ends the process
    }
    int status = 0;
    ASSERT_EQ(::waitpid(child, &status, 0), child);
    EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == signo) << "signal " << signo << ": status " << status;
    EXPECT_FALSE(fs::exists(tmp)) << "signal " << signo << " left " << tmp;
  }
  fs::remove_all(dir);
}
