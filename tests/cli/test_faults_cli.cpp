// Fault injection against the CLI's data-safety contract (docs/data-safety.md): standard output
// on a full device, a full disk (a small tmpfs, mounted where the test may), a study killed by
// SIGTERM mid-run and resumed, and outputs that reach an input through another name.
#include <gtest/gtest.h>

#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <thread>
#include <vector>

#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {

fs::path temp_dir(const std::string& name) { return clearshape::testing::fresh_temp_dir("clearshape_faults_" + name); }
std::string read(const fs::path& p) { return clearshape::testing::read_bytes(p); }
void write(const fs::path& p, const std::string& text) { std::ofstream(p, std::ios::binary) << text; }
fs::path studies() { return fs::path(CLEARSHAPE_GOLDEN_DIR).parent_path().parent_path() / "studies"; }

// Every file under `dir` (relative path → bytes).
std::map<std::string, std::string> tree(const fs::path& dir) {
  std::map<std::string, std::string> files;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.is_regular_file()) files[fs::relative(e.path(), dir).string()] = read(e.path());
  }
  return files;
}
std::size_t temporaries(const fs::path& dir) {
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir)) n += e.path().filename().string().find(".tmp") != std::string::npos;
  return n;
}

// A tmpfs of `bytes` (rounded up to whole pages) at `dir`, unmounted on scope exit; `mounted()`
// is false where mounting is not permitted (not root, no CAP_SYS_ADMIN, a container).
class SmallDisk {
 public:
  SmallDisk(fs::path dir, std::size_t bytes) : dir_(std::move(dir)) {
    fs::create_directories(dir_);
    mounted_ = std::system(("mount -t tmpfs -o size=" + std::to_string(bytes) + " clearshape-test " + dir_.string() +
                            " 2>/dev/null").c_str()) == 0;
  }
  ~SmallDisk() {
    if (mounted_) (void)std::system(("umount " + dir_.string()).c_str());
  }
  SmallDisk(const SmallDisk&) = delete;
  SmallDisk& operator=(const SmallDisk&) = delete;
  bool mounted() const { return mounted_; }
  const fs::path& dir() const { return dir_; }

 private:
  fs::path dir_;
  bool mounted_ = false;
};
const std::size_t kPage = static_cast<std::size_t>(::sysconf(_SC_PAGESIZE));
std::size_t pages(std::size_t bytes) { return (bytes + kPage - 1) / kPage; }

}  // namespace

TEST(FaultsCli, StandardOutputOnAFullDeviceIsAFailureInEveryPrintingSubcommand) {
  const fs::path d = temp_dir("stdout");
  ASSERT_EQ(run_cli("simulate --duration 0.3 -o " + (d / "run.csv").string()).exit_code, 0);
  const std::string run = (d / "run.csv").string();
  const std::vector<std::string> commands{
      "demo --duration 0.5 --out " + (d / "demo").string(),
      "sensitivity --method zv --frequency-hz 10 --zeta 0.1",
      "simulate --duration 0.1 --json",
      "identify --data " + run + " --input-column command_deg --output-column motor_deg --model P1",
      "modes --data " + run + " --output-column link_deg_s --modes 1",
      "frf --in " + run + " --input motor_deg --output gyro_deg_s",
      "--help",
      "--version"};
  for (const std::string& args : commands) {
    const auto r = run_cli(args + " > /dev/full");
    EXPECT_EQ(r.exit_code, 1) << args << ": " << r.err;
    EXPECT_NE(r.err.find("cannot write to standard output"), std::string::npos) << args << ": " << r.err;
  }
}

TEST(FaultsCli, AFullDiskLeavesTheOldOutputAndNoTemporaries) {
  SmallDisk disk(temp_dir("disk") / "mnt", 4 * kPage);
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root); full-disk test skipped";
  const fs::path out = disk.dir() / "sig.csv";
  write(out, "old\n");
  // 10 s at 1 kHz: far more than the three pages left.
  const auto r = run_cli("signal --type step --amplitude 1 --duration 10 -o " + out.string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("sig.csv"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_EQ(read(out), "old\n");
  EXPECT_EQ(temporaries(disk.dir()), 0u);
}

TEST(FaultsCli, ARunAndItsSidecarOnAFullDiskAppearTogetherOrNotAtAll) {
  // The sizes of the two files, from the same (deterministic) run on a normal folder.
  const fs::path ref = temp_dir("sizes");
  const std::string args = "simulate --duration 0.5 -o ";
  ASSERT_EQ(run_cli(args + (ref / "run.csv").string()).exit_code, 0);
  const std::size_t csv_pages = pages(fs::file_size(ref / "run.csv"));
  const std::size_t json_bytes = fs::file_size(ref / "run.json");
  ASSERT_GT(json_bytes, kPage);             // the sidecar needs 2 pages …
  ASSERT_LT(json_bytes + 512, 3 * kPage);  // … or 3 with a longer path in it
  // Room for the old pair (1 page each), the new CSV and one page more, not for the new
  // sidecar: the CSV's temporary is written, the sidecar's fails, neither replaces the old pair.
  SmallDisk disk(temp_dir("pair") / "mnt", (3 + csv_pages) * kPage);
  if (!disk.mounted()) GTEST_SKIP() << "cannot mount a tmpfs here (needs root); full-disk test skipped";
  write(disk.dir() / "run.csv", "old csv\n");
  write(disk.dir() / "run.json", "{\"old\": true}\n");
  const auto r = run_cli(args + (disk.dir() / "run.csv").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("run.json: write failed: No space left on device"), std::string::npos) << r.err;
  EXPECT_EQ(read(disk.dir() / "run.csv"), "old csv\n");
  EXPECT_EQ(read(disk.dir() / "run.json"), "{\"old\": true}\n");
  EXPECT_EQ(temporaries(disk.dir()), 0u);
  // With the old pair gone there is room for both: the same command writes the same run.
  fs::remove(disk.dir() / "run.csv");
  fs::remove(disk.dir() / "run.json");
  const auto ok = run_cli(args + (disk.dir() / "run.csv").string());
  ASSERT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_EQ(read(disk.dir() / "run.csv"), read(ref / "run.csv"));
  EXPECT_TRUE(fs::exists(disk.dir() / "run.json"));
}

TEST(FaultsCli, AStudyKilledMidRunResumesToTheBytesOfAnUninterruptedOne) {
  const std::string protocol = (studies() / "thesis-position.toml").string();
  const fs::path ref = temp_dir("ref");
  ASSERT_EQ(run_cli("study " + protocol + " --quick --out " + ref.string()).exit_code, 0);

  // The same study, sent SIGTERM once its first run is complete (a sidecar exists) — mid-study.
  const fs::path d = temp_dir("killed");
  const pid_t child = ::fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    const std::string out = d.string();
    (void)std::freopen("/dev/null", "w", stdout);
    (void)std::freopen("/dev/null", "w", stderr);
    ::execl(CLEARSHAPE_CLI, "clearshape", "study", protocol.c_str(), "--quick", "--out", out.c_str(), nullptr);
    ::_exit(127);
  }
  const auto has_finished_run = [&] {
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(d / "runs", ec)) {
      if (e.path().extension() == ".json") return true;
    }
    return false;
  };
  int status = 0;
  bool exited = false;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (!has_finished_run() && std::chrono::steady_clock::now() < deadline) {
    if (::waitpid(child, &status, WNOHANG) == child) {
      exited = true;
      break;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  if (!exited) {
    ::kill(child, SIGTERM);
    ASSERT_EQ(::waitpid(child, &status, 0), child);
  }
  ASSERT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGTERM)
      << "the study was not ended by the signal (it finished or failed first): status " << status;
  EXPECT_FALSE(fs::exists(d / "results.json"));
  EXPECT_EQ(temporaries(d), 0u);  // the handler removed the files in flight

  // A temporary left by a SIGKILL (which cannot be caught) is removed by the resumed run.
  write(d / "runs" / "unshaped__step-20__r01.csv.tmp999999-1", "half a run\n");
  const auto r = run_cli("study " + protocol + " --quick --out " + d.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("reused"), std::string::npos) << r.err;
  auto resumed = tree(d);
  auto uninterrupted = tree(ref);
  resumed.erase("timing.json");  // wall clock
  uninterrupted.erase("timing.json");
  EXPECT_EQ(resumed.size(), uninterrupted.size());
  for (const auto& [name, bytes] : uninterrupted) {
    const auto it = resumed.find(name);
    ASSERT_NE(it, resumed.end()) << name;
    EXPECT_TRUE(it->second == bytes) << name << " differs from the uninterrupted study's";
  }
}

TEST(FaultsCli, AnInputReachedThroughALinkOrASidecarNameIsNeverOverwritten) {
  const fs::path d = temp_dir("links");
  ASSERT_EQ(run_cli("signal --type step --amplitude 1 --duration 0.2 -o " + (d / "in.csv").string()).exit_code, 0);
  const std::string before = read(d / "in.csv");
  fs::create_symlink(d / "in.csv", d / "symlink.csv");
  fs::create_hard_link(d / "in.csv", d / "hardlink.csv");
  for (const char* target : {"symlink.csv", "hardlink.csv"}) {
    const auto r = run_cli("shape --method zv --frequency-hz 10 --zeta 0.1 -i " + (d / "in.csv").string() +
                           " --column command -o " + (d / target).string());
    EXPECT_EQ(r.exit_code, 2) << target << ": " << r.err;
    EXPECT_NE(r.err.find("inputs are never overwritten"), std::string::npos) << r.err;
    EXPECT_EQ(read(d / "in.csv"), before) << target;
  }
  // simulate -o run.csv writes run.json beside it: a rig configuration of that name is an input.
  write(d / "run.json", "[contact]\nstiffness = 40\n");
  const auto r = run_cli("simulate --duration 0.1 --config " + (d / "run.json").string() + " -o " +
                         (d / "run.csv").string());
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_EQ(read(d / "run.json"), "[contact]\nstiffness = 40\n");
  EXPECT_FALSE(fs::exists(d / "run.csv"));  // the pair is refused whole
}
