// Issue 21, "nothing lost": --fresh never removes the recordings a study is about to read; an
// output path that is a device, a FIFO or a folder is refused by name and left as it was, one
// that is a symbolic link replaces the link's target; a recordings manifest names what is wrong
// with a file it lists (not "does not exist") and refuses one recording given to two runs.
#include <gtest/gtest.h>

#include <sys/stat.h>
#include <sys/sysmacros.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>

#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::read_bytes;
using clearshape::testing::run_cli;

namespace {

fs::path temp_dir(const std::string& name) { return clearshape::testing::fresh_temp_dir("clearshape_lost_" + name); }

std::map<std::string, std::string> files_in(const fs::path& dir) {
  std::map<std::string, std::string> out;
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.is_regular_file()) out[e.path().filename().string()] = read_bytes(e.path());
  }
  return out;
}

// A finished quick study in `out`, and a recordings manifest in out/runs naming its own runs.
void study_with_recordings_in_its_runs(const fs::path& out, const std::string& protocol) {
  ASSERT_EQ(run_cli("study " + protocol + " --quick --out " + out.string()).exit_code, 0);
  const auto manifest = run_cli("study " + protocol + " --quick --print-manifest");
  ASSERT_EQ(manifest.exit_code, 0) << manifest.err;
  std::ofstream(out / "runs" / "manifest.toml") << manifest.out;
}

}  // namespace

// Item 1: `study --recordings OUT/runs --out OUT --fresh` deleted all the recordings and their
// sidecars it was about to read. They are inputs now: --fresh keeps them, byte for byte.
TEST(NothingLostCli, FreshNeverDeletesTheRecordingsTheStudyReads) {
  const fs::path out = temp_dir("fresh_inputs");
  const std::string protocol = clearshape::testing::studies_path("thesis-position.toml").string();
  study_with_recordings_in_its_runs(out, protocol);
  const auto before = files_in(out / "runs");
  ASSERT_GT(before.size(), 10u);
  const auto r = run_cli("study " + protocol + " --quick --recordings " + (out / "runs").string() + " --out " +
                         out.string() + " --fresh");
  EXPECT_NE(r.err.find("kept"), std::string::npos) << r.err;
  const auto after = files_in(out / "runs");
  EXPECT_EQ(after.size(), before.size()) << r.err;
  for (const auto& [name, bytes] : before) {
    ASSERT_TRUE(after.count(name)) << name << " was removed; " << r.err;
    EXPECT_EQ(after.at(name), bytes) << name;
  }
}

// Item 2: `signal -o n` replaced a character device or a FIFO by a regular file (as root,
// `-o /dev/null` replaced the system's /dev/null). Now: exit 2 naming the path, the node kept.
TEST(NothingLostCli, AnOutputThatIsADeviceOrAFifoIsRefusedAndALinkKeepsItsTarget) {
  const fs::path d = temp_dir("special");
  ASSERT_EQ(::mkfifo((d / "fifo").c_str(), 0600), 0);
  std::vector<fs::path> refused = {d / "fifo"};
  if (::mknod((d / "n").c_str(), S_IFCHR | 0666, makedev(1, 3)) == 0) refused.push_back(d / "n");  // root only
  fs::create_directories(d / "folder");
  refused.push_back(d / "folder");
  for (const fs::path& out : refused) {
    const auto r = run_cli("signal --type step --amplitude 1 --duration 0.1 -o " + out.string());
    EXPECT_EQ(r.exit_code, 2) << out << ": " << r.err;
    EXPECT_NE(r.err.find(out.string()), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("not a regular file"), std::string::npos) << r.err;
  }
  EXPECT_TRUE(fs::is_fifo(d / "fifo"));
  if (refused.size() == 4) {
    EXPECT_TRUE(fs::is_character_file(d / "n"));
  }
  EXPECT_TRUE(fs::is_directory(d / "folder"));
  // A link: its target gets the output, the link stays a link.
  std::ofstream(d / "target.csv") << "old\n";
  fs::create_symlink("target.csv", d / "link.csv");
  const auto r = run_cli("signal --type step --amplitude 1 --duration 0.1 -o " + (d / "link.csv").string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(fs::is_symlink(fs::symlink_status(d / "link.csv")));
  EXPECT_EQ(read_bytes(d / "target.csv").rfind("time_s", 0), 0u) << read_bytes(d / "target.csv");
}

// The manifest's messages: what is wrong with a listed file; one recording is one run.
TEST(NothingLostCli, ARecordingsManifestNamesWhatIsWrongWithAFile) {
  const fs::path d = temp_dir("manifest");
  const std::string protocol = clearshape::testing::studies_path("thesis-position.toml").string();
  const auto none = run_cli("study " + protocol + " --quick --recordings " + d.string() + " --out " +
                            (d / "out").string());
  EXPECT_EQ(none.exit_code, 2) << none.err;
  EXPECT_NE(none.err.find("cannot read the recordings manifest: it does not exist"), std::string::npos) << none.err;
  const auto manifest = run_cli("study " + protocol + " --quick --print-manifest");
  ASSERT_EQ(manifest.exit_code, 0);
  const auto id_at = manifest.out.find("\nid = \"");
  ASSERT_NE(id_at, std::string::npos);
  const std::string id = manifest.out.substr(id_at + 7, manifest.out.find('"', id_at + 7) - (id_at + 7));
  const std::string head = "format = \"clearshape-recordings/1\"\n";
  ASSERT_EQ(::mkfifo((d / "fifo.csv").c_str(), 0600), 0);
  fs::create_directories(d / "folder.csv");
  for (const auto& [file, says] : {std::pair<std::string, std::string>{"fifo.csv", "is a FIFO (named pipe)"},
                                   {"folder.csv", "is a folder"},
                                   {"/dev/null", "is a character device"}}) {
    std::ofstream(d / "manifest.toml") << head << "\n[[run]]\nid = \"" << id << "\"\nfile = \"" << file << "\"\n";
    const auto r = run_cli("study " + protocol + " --quick --recordings " + d.string() + " --out " +
                           (d / "out").string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(says), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("does not exist"), std::string::npos) << r.err;
  }
  // The same CSV for two runs.
  ASSERT_EQ(run_cli("signal --type step --amplitude 1 --duration 0.1 -o " + (d / "one.csv").string()).exit_code, 0);
  const std::string id2 = id.substr(0, id.rfind('/') + 1) + "r02";
  std::ofstream(d / "manifest.toml") << head << "\n[[run]]\nid = \"" << id << "\"\nfile = \"one.csv\"\n"
                                     << "\n[[run]]\nid = \"" << id2 << "\"\nfile = \"./one.csv\"\n";
  const auto twice = run_cli("study " + protocol + " --quick --recordings " + d.string() + " --out " +
                             (d / "out").string());
  EXPECT_EQ(twice.exit_code, 2) << twice.err;
  EXPECT_NE(twice.err.find("is already the recording of run '" + id + "'"), std::string::npos) << twice.err;
  EXPECT_FALSE(fs::exists(d / "out"));
}

// The exit-code list: a recording with a value of 1e308 ended as "every one of 9 model
// simulations failed", naming no file or row; `--max-delay-s ""` was read as 0.
TEST(MessagesCli, AnAbsurdRecordedValueIsNamedByFileLineAndColumn) {
  const fs::path out = temp_dir("absurd");
  const std::string protocol = clearshape::testing::studies_path("thesis-position.toml").string();
  study_with_recordings_in_its_runs(out, protocol);
  const std::string manifest = read_bytes(out / "runs" / "manifest.toml");
  const auto file_at = manifest.find("\nfile = \"");
  ASSERT_NE(file_at, std::string::npos);
  const std::string file = manifest.substr(file_at + 9, manifest.find('"', file_at + 9) - (file_at + 9));
  const fs::path csv = out / "runs" / file;
  std::ifstream in(csv);
  std::string header, line, text;
  std::getline(in, header);
  text = header + "\n";
  std::size_t column = 0;
  for (std::size_t pos = 0, k = 0; pos != std::string::npos; ++k) {
    const std::size_t next = header.find(',', pos);
    if (header.substr(pos, next == std::string::npos ? next : next - pos) == "motor_angle_deg") column = k;
    pos = next == std::string::npos ? next : next + 1;
  }
  ASSERT_GT(column, 0u) << header;
  for (int row = 0; std::getline(in, line); ++row) {
    if (row == 10) {  // file line 12
      std::size_t pos = 0;
      for (std::size_t k = 0; k < column; ++k) pos = line.find(',', pos) + 1;
      line.replace(pos, line.find(',', pos) - pos, "1e308");
    }
    text += line + "\n";
  }
  in.close();
  std::ofstream(csv, std::ios::trunc) << text;
  const auto r = run_cli("study " + protocol + " --quick --recordings " + (out / "runs").string() + " --out " +
                         (out / "again").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find(file + ":12"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("motor_angle_deg"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("value 1e+308 is not a measurement; allowed: within ±1e+09"), std::string::npos) << r.err;

  const auto empty = run_cli("signal --type step --amplitude \"\" --duration 0.1 -o " + (out / "s.csv").string());
  EXPECT_EQ(empty.exit_code, 2) << empty.err;
  EXPECT_NE(empty.err.find("--amplitude"), std::string::npos) << empty.err;
  EXPECT_NE(empty.err.find("an empty value is not a number"), std::string::npos) << empty.err;
  EXPECT_FALSE(fs::exists(out / "s.csv"));

  // CLI11's positive-number check stated DBL_MAX in full (a 309-digit bound).
  const auto window = run_cli("fit-clearance --window-s 0");
  EXPECT_EQ(window.exit_code, 2) << window.err;
  EXPECT_NE(window.err.find("0 is out of range; allowed: > 0"), std::string::npos) << window.err;
  EXPECT_EQ(window.err.find("179769"), std::string::npos) << window.err;
}

// Issue 21 item 7: a protocol of 9·10⁸-sample records passed validation and ended in
// std::bad_alloc after the study had made its output folder. Its memory is estimated from the
// protocol and refused, with the numbers and the option that allows it, before anything exists.
TEST(NothingLostCli, AProtocolTooLargeForMemoryIsRefusedBeforeAnyOutput) {
  const fs::path d = temp_dir("huge");
  std::string text = read_bytes(clearshape::testing::studies_path("thesis-position.toml"));
  for (const auto& [from, to] : {std::pair<std::string, std::string>{"sample_rate_hz = 1000.0", "sample_rate_hz = 100000.0"},
                                 {"record_s = 5.0 ", "record_s = 9000.0 "}}) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  std::ofstream(d / "huge.toml") << text;
  const auto start = std::chrono::steady_clock::now();
  const auto r = run_cli("study " + (d / "huge.toml").string() + " --out " + (d / "out").string());
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(10));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("too large for memory: records of 9e+08 samples (9000 s at 100000 Hz)"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("--max-memory-gb"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(d / "out")) << "the study created its folder before refusing";
}
