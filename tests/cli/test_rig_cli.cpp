// `clearshape rig probe|stream|run` and `study --rig serial:…` against the board double
// (tests/support/board_double.hpp) on a pseudo-terminal: the child process opens its slave side.
#include <gtest/gtest.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "support/board_double.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

extern char** environ;

namespace fs = std::filesystem;
using clearshape::testing::BoardDouble;
using clearshape::testing::run_cli;

namespace {

fs::path temp(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("clearshape_rig_cli_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir / name;
}

nlohmann::json read_json(const fs::path& p) {
  std::ifstream in(p);
  return nlohmann::json::parse(in);
}

TEST(RigCli, ProbePrintsFirmwareCapabilitiesAndSelfTest) {
  BoardDouble board;
  board.start();
  const auto r = run_cli("rig probe --port " + board.path());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("firmware        1.2.3"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("wire protocol   v1"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("encoder-quadrature, pulse-ab, dac-mcp4725, gyro-itg3205, servo-on, watchdog"), std::string::npos);
  EXPECT_NE(r.out.find("gyro WHO_AM_I 0x69 ok, DAC ok, gyro at rest -2 LSB"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("samples sent 1234"), std::string::npos) << r.out;

  const auto j = run_cli("rig probe --json --port " + board.path());
  ASSERT_EQ(j.exit_code, 0) << j.err;
  const auto doc = nlohmann::json::parse(j.out);
  EXPECT_EQ(doc["board"]["firmware_version"], "1.2.3");
  EXPECT_EQ(doc["board"]["selftest"]["gyro_who_am_i"], 0x69);
  EXPECT_TRUE(doc["selftest_passed"].get<bool>());
}

TEST(RigCli, ProbeErrorsNameThePortAndTheOption) {
  const auto missing = run_cli("rig probe --port /dev/ttyCLEARSHAPE_NONE");
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.err.find("no such port"), std::string::npos) << missing.err;
  // A path that exists but is no serial port is named for what it is (it was "no such port").
  const auto file = run_cli("rig probe --port " + std::string(CLEARSHAPE_GOLDEN_DIR));
  EXPECT_EQ(file.exit_code, 1);
  EXPECT_NE(file.err.find("is a folder, not a serial device"), std::string::npos) << file.err;
  const auto device = run_cli("rig probe --port /dev/null");
  EXPECT_EQ(device.exit_code, 1);
  EXPECT_NE(device.err.find("is a character device but not a serial port"), std::string::npos) << device.err;
  const auto rate = run_cli("rig probe --port /dev/ttyCLEARSHAPE_NONE --rate 5000");
  EXPECT_EQ(rate.exit_code, 2);
  EXPECT_NE(rate.err.find("--rate"), std::string::npos) << rate.err;
  // The real ranges (issue 21): no flipped sign, no 64-bit bound.
  const auto handshake = run_cli("rig probe --port /dev/ttyCLEARSHAPE_NONE --handshake-timeout-s 0");
  EXPECT_EQ(handshake.exit_code, 2);
  EXPECT_NE(handshake.err.find("--handshake-timeout-s = 0 is out of range; allowed: (0, 60] s"), std::string::npos)
      << handshake.err;
  const auto pulses = run_cli("rig probe --port /dev/ttyCLEARSHAPE_NONE --max-pulse-hz -1");
  EXPECT_EQ(pulses.exit_code, 2);
  EXPECT_NE(pulses.err.find("--max-pulse-hz = -1 is out of range; allowed: 1 … 45000"), std::string::npos)
      << pulses.err;
  const fs::path protocol = fs::path(CLEARSHAPE_GOLDEN_DIR).parent_path().parent_path() / "studies" / "thesis-position.toml";
  const auto absent = run_cli("study " + protocol.string() + " --quick --rig 'serial:/dev/ttyCLEARSHAPE_NONE?baud=115200' --out " +
                              temp("absent").string());
  EXPECT_EQ(absent.exit_code, 1);
  EXPECT_NE(absent.err.find("rig serial:/dev/ttyCLEARSHAPE_NONE at 115200 baud"), std::string::npos) << absent.err;
  EXPECT_NE(absent.err.find("no such port"), std::string::npos) << absent.err;
  const auto spec = run_cli("study studies/thesis-position.toml --rig usb:/dev/ttyACM0");
  EXPECT_EQ(spec.exit_code, 2);
  EXPECT_NE(spec.err.find("serial:PORT?baud=N"), std::string::npos) << spec.err;
  const auto fraction = run_cli("study studies/thesis-position.toml --rig 'serial:/dev/ttyACM0?baud=115200&max_late_fraction=2'");
  EXPECT_EQ(fraction.exit_code, 2);
  EXPECT_NE(fraction.err.find("&max_late_fraction=F (F in 0 … 1)"), std::string::npos) << fraction.err;
}

TEST(RigCli, RunWritesTheCommandAndSensorsWithASidecar) {
  BoardDouble board;
  board.start();
  const auto csv = temp("step.csv");
  const auto r = run_cli("rig run --port " + board.path() +
                         " --signal step --amplitude 9 --start-s 0.05 --duration 0.2 --no-realtime --max-late-fraction 1 -o " + csv.string() +
                         " --shaper zv --shaper-frequency-hz 10 --shaper-zeta 0.1");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const auto table = clearshape::io::read_table(csv);
  ASSERT_EQ(table.rows(), 201u);
  EXPECT_EQ(table.names, (std::vector<std::string>{"time_s", "command_deg", "command_shaped_deg", "command_applied_deg",
                                                   "encoder_counts", "motor_deg", "gyro_raw", "gyro_deg_s", "flags",
                                                   "latency_s"}));
  EXPECT_DOUBLE_EQ(table.column("time_s")[100], 0.1);
  EXPECT_DOUBLE_EQ(table.column("command_deg").back(), 9.0);
  EXPECT_DOUBLE_EQ(table.column("command_shaped_deg").back(), 9.0);  // ZV ends within 0.05 s
  EXPECT_DOUBLE_EQ(table.column("encoder_counts")[10], 30.0);       // the double's 3·tick
  EXPECT_NEAR(table.column("motor_deg")[10], 30 * 360.0 / 12000, 1e-12);
  const auto side = read_json(fs::path(csv).replace_extension(".json"));
  EXPECT_TRUE(side["complete"].get<bool>());
  EXPECT_EQ(side["rig"]["kind"], "physical");
  EXPECT_EQ(side["statistics"]["samples"], 201);
  EXPECT_EQ(side["statistics"]["samples_lost"], 0);
  EXPECT_EQ(side["shaper"]["method"], "zv");
  board.stop();
  // The last target: 9° = 300 pulses at 12000 pulses per revolution.
  ASSERT_FALSE(board.commands.empty());
  EXPECT_EQ(board.commands.back(), 300);
}

TEST(RigCli, LostSamplesMarkTheRecordIncomplete) {
  BoardDouble board;
  board.on_sample = [](BoardDouble::Sample& s) { return s.tick != 40; };
  board.start();
  const auto stream_csv = temp("stream.csv");
  const auto s = run_cli("rig stream --port " + board.path() + " --duration 0.1 --no-realtime -o " + stream_csv.string());
  EXPECT_EQ(s.exit_code, 1) << s.err;  // a stream with holes is a failure too (issue 21 item 5)
  EXPECT_NE(s.err.find("1 sample(s) lost"), std::string::npos) << s.err;
  EXPECT_FALSE(fs::exists(stream_csv));  // written apart, under a name that says so
  const auto side = read_json(temp("stream.incomplete.json"));
  EXPECT_FALSE(side["complete"].get<bool>());
  EXPECT_EQ(side["statistics"]["samples_lost"], 1);
  EXPECT_FALSE(side["configuration"]["servo_on"].get<bool>());
  EXPECT_EQ(clearshape::io::read_table(temp("stream.incomplete.csv")).names.front(), "time_s");

  BoardDouble board2;
  board2.on_sample = [](BoardDouble::Sample& smp) { return smp.tick != 40; };
  board2.start();
  const auto run_csv = temp("run.csv");
  const auto r = run_cli("rig run --port " + board2.path() + " --signal step --amplitude 1 --duration 0.1 --no-realtime -o " +
                         run_csv.string());
  EXPECT_EQ(r.exit_code, 1);  // a run refuses
  EXPECT_NE(r.err.find("is not complete: 1 sample(s) lost"), std::string::npos) << r.err;
  EXPECT_FALSE(read_json(temp("run.incomplete.json"))["complete"].get<bool>());

  // Offered to a study as a recording, the incomplete run is refused by name.
  const fs::path protocol = fs::path(CLEARSHAPE_GOLDEN_DIR).parent_path().parent_path() / "studies" / "thesis-position.toml";
  const auto manifest = run_cli("study " + protocol.string() + " --quick --print-manifest");
  ASSERT_EQ(manifest.exit_code, 0) << manifest.err;
  const auto id_at = manifest.out.find("\nid = \"");
  ASSERT_NE(id_at, std::string::npos);
  const std::string id = manifest.out.substr(id_at + 7, manifest.out.find('"', id_at + 7) - (id_at + 7));
  {
    std::ofstream m(temp("manifest.toml"));
    m << "format = \"clearshape-recordings/1\"\n[columns]\ntime = \"time_s\"\ncommand = \"command_deg\"\n"
         "command_unit = \"deg\"\nmotor_angle = \"motor_deg\"\nmotor_angle_unit = \"deg\"\n"
         "link_rate = \"gyro_deg_s\"\nlink_rate_unit = \"deg/s\"\n";
    // Every repetition of the first input (a stage runs only when it has all its runs).
    // (one recording is one run: a copy of the incomplete record, with its sidecar, for each)
    for (const std::string rep : {"r01", "r02", "r03"}) {
      fs::copy_file(temp("run.incomplete.csv"), temp(rep + ".csv"), fs::copy_options::overwrite_existing);
      fs::copy_file(temp("run.incomplete.json"), temp(rep + ".json"), fs::copy_options::overwrite_existing);
      m << "\n[[run]]\nid = \"" << id.substr(0, id.rfind('/') + 1) << rep << "\"\nfile = \"" << rep << ".csv\"\n";
    }
  }
  const auto study = run_cli("study " + protocol.string() + " --quick --recordings " + temp("").string() + " --out " +
                             temp("study").string());
  EXPECT_EQ(study.exit_code, 2) << study.err;
  EXPECT_NE(study.err.find("r01.csv is incomplete (1 sample(s) lost"), std::string::npos) << study.err;
}

// Issue 21 item 3: a failed `rig run -o keep.csv` replaced the previous keep.csv and keep.json
// with its incomplete record. They stay; the incomplete record goes to keep.incomplete.csv/.json.
TEST(RigCli, AFailedRunLeavesThePreviousRecordAndWritesItsOwnApart) {
  BoardDouble board;
  board.on_sample = [](BoardDouble::Sample& smp) { return smp.tick != 30; };
  board.start();
  const auto keep = temp("keep.csv");
  { std::ofstream(keep) << "time_s,x\n0,1\n"; }
  { std::ofstream(temp("keep.json")) << "{\"complete\": true}\n"; }
  const auto r = run_cli("rig run --port " + board.path() + " --signal step --amplitude 1 --duration 0.1 --no-realtime -o " +
                         keep.string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_EQ(clearshape::testing::read_bytes(keep), "time_s,x\n0,1\n");
  EXPECT_EQ(clearshape::testing::read_bytes(temp("keep.json")), "{\"complete\": true}\n");
  EXPECT_NE(r.err.find("keep.incomplete.csv"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(keep.string() + " was left as it was"), std::string::npos) << r.err;
  const auto side = read_json(temp("keep.incomplete.json"));
  EXPECT_FALSE(side["complete"].get<bool>());
  EXPECT_EQ(side["csv"], temp("keep.incomplete.csv").string());
  // Each of the 101 cycles read a sample; tick 30 is missing from them (flagged on tick 31).
  EXPECT_EQ(clearshape::io::read_table(temp("keep.incomplete.csv")).column("time_s")[30], 0.031);
}

// Issue 21 item 5: commands that did not reach the drive (the watchdog held it, the board
// rejected host frames) and samples late beyond --max-late-fraction make a run degraded: never
// "complete", exit 1, each reason counted in the sidecar.
TEST(RigCli, ADegradedRunIsNeverComplete) {
  struct Case {
    const char* name;
    std::function<bool(BoardDouble::Sample&)> flag;
    std::function<double(std::uint32_t)> delay;
    const char* says;
  };
  const Case cases[] = {
      {"watchdog", [](BoardDouble::Sample& smp) { if (smp.tick >= 50) smp.flags |= CS_SAMPLE_WATCHDOG; return true; },
       nullptr, "51 sample(s) taken while the board's watchdog held the command safe"},
      {"rejected", [](BoardDouble::Sample& smp) { if (smp.tick == 70) smp.flags |= CS_SAMPLE_RX_REJECTED; return true; },
       nullptr, "the board rejected 0 host frame(s) (COMMANDs lost; 1 sample(s) flagged)"},
      {"late", nullptr, [](std::uint32_t tick) { return tick == 40 ? 0.04 : 0.0; }, "samples arrived later than 5 ms"},
  };
  for (const Case& c : cases) {
    BoardDouble board;
    board.on_sample = c.flag;
    board.delay_before_s = c.delay;
    board.start();
    const auto csv = temp(std::string(c.name) + ".csv");
    const auto r = run_cli("rig run --port " + board.path() + " --signal step --amplitude 1 --duration 0.1 "
                           "--no-realtime -o " + csv.string());
    EXPECT_EQ(r.exit_code, 1) << c.name << ": " << r.err;
    EXPECT_NE(r.err.find(c.says), std::string::npos) << c.name << ": " << r.err;
    EXPECT_FALSE(fs::exists(csv)) << c.name;
    const auto side = read_json(temp(std::string(c.name) + ".incomplete.json"));
    EXPECT_FALSE(side["complete"].get<bool>()) << c.name;
    ASSERT_FALSE(side["degraded"].empty()) << c.name;
    EXPECT_NE(side["degraded"][0].get<std::string>().find(c.says), std::string::npos) << side["degraded"];
  }
  // The same late run with a tolerance that allows it is complete.
  BoardDouble board;
  board.delay_before_s = [](std::uint32_t tick) { return tick == 40 ? 0.04 : 0.0; };
  board.start();
  const auto r = run_cli("rig run --port " + board.path() + " --signal step --amplitude 1 --duration 0.1 --no-realtime "
                         "--max-late-fraction 1 -o " + temp("allowed.csv").string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(read_json(temp("allowed.json"))["complete"].get<bool>());
  const auto stats = read_json(temp("allowed.json"))["statistics"];
  EXPECT_GT(stats["samples_late"].get<int>(), 1);
  // Issue 21 item 6: a late cycle's command superseded at once by a newer one is coalesced, not
  // written; every cycle's command is either sent or counted as coalesced.
  ASSERT_TRUE(stats.contains("commands_coalesced")) << stats;
  EXPECT_EQ(stats["commands_sent"].get<int>() + stats["commands_coalesced"].get<int>(), stats["samples"].get<int>());
}

// Issue 21 item 5: `study --rig serial:` used a degraded run as a trial. A run whose samples came
// late beyond the tolerance (a host stall) now fails the study, naming the run and the reason.
TEST(RigCli, AStudyRefusesADegradedRunOnTheSerialRig) {
  BoardDouble board;
  board.delay_before_s = [](std::uint32_t tick) { return tick == 100 ? 0.2 : 0.0; };  // every run stalls
  board.start();
  const fs::path protocol = fs::path(CLEARSHAPE_GOLDEN_DIR).parent_path().parent_path() / "studies" / "thesis-position.toml";
  const auto r = run_cli("study " + protocol.string() + " --quick --rig serial:" + board.path() + " --out " +
                         temp("degraded_study").string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("the rig's record is degraded"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("samples arrived later than 5 ms"), std::string::npos) << r.err;
}

// Issue 21 item 4: SIGINT during `rig stream --servo-on` ended the process at once: no STOP, the
// servo left on. Now the loop ends, STOP is sent (servo off), the incomplete record is written
// apart, and the signal then ends the process as usual.
TEST(RigCli, SigintDuringAStreamWithTheServoOnSendsStop) {
  BoardDouble board;
  board.start();
  const auto csv = temp("sigint.csv");
  const auto err = temp("sigint.err");
  const std::string command = std::string("exec ") + CLEARSHAPE_CLI + " rig stream --servo-on --port " + board.path() +
                              " --duration 30 --no-realtime -o " + csv.string() + " 2>" + err.string();
  pid_t pid = -1;
  const char* argv[] = {"/bin/sh", "-c", command.c_str(), nullptr};
  ASSERT_EQ(posix_spawn(&pid, "/bin/sh", nullptr, nullptr, const_cast<char* const*>(argv), environ), 0);
  // Wait until the stream runs with the servo on.
  for (int i = 0; i < 500 && !(board.started && board.servo_on); ++i) usleep(10'000);
  ASSERT_TRUE(board.started && board.servo_on);
  usleep(200'000);
  ::kill(pid, SIGINT);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == SIGINT) << "status " << status;
  const std::string text = clearshape::testing::read_bytes(err);
  board.stop();
  EXPECT_FALSE(board.started) << text;
  EXPECT_FALSE(board.servo_on) << text;
  ASSERT_FALSE(board.received.empty());
  EXPECT_NE(std::find(board.received.begin(), board.received.end(), CS_MSG_STOP), board.received.end());
  EXPECT_NE(text.find("interrupted by SIGINT"), std::string::npos) << text;
  EXPECT_NE(text.find("STOP confirmed"), std::string::npos) << text;
  EXPECT_FALSE(fs::exists(csv));
  EXPECT_FALSE(read_json(temp("sigint.incomplete.json"))["complete"].get<bool>());
}

}  // namespace
