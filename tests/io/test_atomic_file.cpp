// The safe-file layer: inputs are never outputs, a batch appears whole or not at all, temporary
// names are recognised (and only they are), one BOM rule.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "clearshape/core/error.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/table.hpp"

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
std::string read(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}
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
  fs::create_directories(dir / "b.csv");  // a folder where a file must go: its rename fails
  fs::create_directories(dir / "b.csv" / "keep");
  io::AtomicBatch batch;
  batch.add(dir / "b.csv", "new b");
  batch.add(dir / "a.csv", "new a");
  EXPECT_THROW(batch.commit(), clearshape::RuntimeError);
  EXPECT_EQ(read(dir / "a.csv"), "old a");  // renamed only after every write and in order: b first
  for (const auto& e : fs::directory_iterator(dir)) {
    EXPECT_FALSE(io::is_temporary_name(e.path().filename().string())) << e.path();
  }
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
