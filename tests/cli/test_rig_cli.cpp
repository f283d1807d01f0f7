// `clearshape rig probe|stream|run` and `study --rig serial:…` against the board double
// (tests/support/board_double.hpp) on a pseudo-terminal: the child process opens its slave side.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "support/board_double.hpp"
#include "support/cli.hpp"

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
  const auto rate = run_cli("rig probe --port /dev/ttyCLEARSHAPE_NONE --rate 5000");
  EXPECT_EQ(rate.exit_code, 2);
  EXPECT_NE(rate.err.find("--rate"), std::string::npos) << rate.err;
  const fs::path protocol = fs::path(CLEARSHAPE_GOLDEN_DIR).parent_path().parent_path() / "studies" / "thesis-position.toml";
  const auto absent = run_cli("study " + protocol.string() + " --quick --rig 'serial:/dev/ttyCLEARSHAPE_NONE?baud=115200' --out " +
                              temp("absent").string());
  EXPECT_EQ(absent.exit_code, 1);
  EXPECT_NE(absent.err.find("rig serial:/dev/ttyCLEARSHAPE_NONE at 115200 baud"), std::string::npos) << absent.err;
  EXPECT_NE(absent.err.find("no such port"), std::string::npos) << absent.err;
  const auto spec = run_cli("study studies/thesis-position.toml --rig usb:/dev/ttyACM0");
  EXPECT_EQ(spec.exit_code, 2);
  EXPECT_NE(spec.err.find("serial:PORT?baud=N"), std::string::npos) << spec.err;
}

TEST(RigCli, RunWritesTheCommandAndSensorsWithASidecar) {
  BoardDouble board;
  board.start();
  const auto csv = temp("step.csv");
  const auto r = run_cli("rig run --port " + board.path() +
                         " --signal step --amplitude 9 --start-s 0.05 --duration 0.2 --no-realtime -o " + csv.string() +
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
  EXPECT_EQ(s.exit_code, 0) << s.err;  // a stream warns
  EXPECT_NE(s.err.find("1 sample(s) lost"), std::string::npos) << s.err;
  const auto side = read_json(fs::path(stream_csv).replace_extension(".json"));
  EXPECT_FALSE(side["complete"].get<bool>());
  EXPECT_EQ(side["statistics"]["samples_lost"], 1);
  EXPECT_FALSE(side["configuration"]["servo_on"].get<bool>());
  EXPECT_EQ(clearshape::io::read_table(stream_csv).names.front(), "time_s");

  BoardDouble board2;
  board2.on_sample = [](BoardDouble::Sample& smp) { return smp.tick != 40; };
  board2.start();
  const auto run_csv = temp("run.csv");
  const auto r = run_cli("rig run --port " + board2.path() + " --signal step --amplitude 1 --duration 0.1 --no-realtime -o " +
                         run_csv.string());
  EXPECT_EQ(r.exit_code, 1);  // a run refuses
  EXPECT_NE(r.err.find("must not be used as a complete run"), std::string::npos) << r.err;
  EXPECT_FALSE(read_json(fs::path(run_csv).replace_extension(".json"))["complete"].get<bool>());

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
    for (const char* rep : {"r01", "r02", "r03"}) {
      m << "\n[[run]]\nid = \"" << id.substr(0, id.rfind('/') + 1) << rep << "\"\nfile = \"run.csv\"\n";
    }
  }
  const auto study = run_cli("study " + protocol.string() + " --quick --recordings " + temp("").string() + " --out " +
                             temp("study").string());
  EXPECT_EQ(study.exit_code, 2) << study.err;
  EXPECT_NE(study.err.find("run.csv is incomplete (1 sample(s) lost"), std::string::npos) << study.err;
}

}  // namespace
