// `clearshape study --recordings`: the quick simulated study's own runs, exported as a
// recordings folder, replayed through the study (exactly, and with renamed columns in other
// units), and a folder with a run missing (its stages skipped, by name, in stderr and
// results.json). Cost: one quick simulated study and three study passes on recordings.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>

#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::run_cli;
using json = nlohmann::json;

namespace {

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
}

std::filesystem::path protocol() {
  return clearshape::testing::golden_path("").parent_path().parent_path().parent_path() / "studies" /
         "thesis-position.toml";
}

json read_json(const std::filesystem::path& p) {
  std::ifstream in(p);
  return json::parse(in);
}

void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream f(p, std::ios::binary);
  f << text;
}

// The manifest template with its [columns] block replaced and, optionally, one run removed.
std::string edit_manifest(std::string manifest, const std::string& columns, const std::string& drop_id) {
  if (!columns.empty()) {
    const auto a = manifest.find("\n[columns]") + 1;
    const auto b = manifest.find("\n[[run]]") + 1;
    manifest.replace(a, b - a, columns + "\n");
  }
  if (!drop_id.empty()) {
    const auto id = manifest.find("id = \"" + drop_id + "\"");
    const auto a = manifest.rfind("\n[[run]]", id) + 1;
    const auto b = manifest.find("\n[[run]]", id);
    manifest.erase(a, b == std::string::npos ? std::string::npos : b + 1 - a);
  }
  return manifest;
}

// A run CSV rewritten with other names and units: t, cmd_rad and drive_rad (the command and the
// applied command in rad), enc (counts), gyro (rad/s).
void convert_run(const std::filesystem::path& from, const std::filesystem::path& to) {
  const auto t = clearshape::io::read_table(from);
  std::ostringstream s;
  s << "t,cmd_rad,drive_rad,enc,gyro_rad_s\n";
  const auto& time = t.column("time_s");
  const auto& cmd = t.column("command_deg");
  const auto& applied = t.column("command_applied_deg");
  const auto& enc = t.column("encoder_counts");
  const auto& rate = t.column("link_rate_deg_s");
  for (std::size_t k = 0; k < t.rows(); ++k) {
    s << fmt::format("{},{},{},{},{}\n", time[k], cmd[k] * std::numbers::pi / 180.0, applied[k] * std::numbers::pi / 180.0, enc[k],
                     rate[k] * std::numbers::pi / 180.0);
  }
  write_text(to, s.str());
}

const json& table(const json& results, const std::string& id) {
  for (const auto& t : results.at("tables")) {
    if (t.at("id") == id) return t;
  }
  throw std::runtime_error("no table " + id);
}

json without_notes(json tables) {
  for (auto& t : tables) t.erase("note");
  return tables;
}

}  // namespace

TEST(StudyRecordingsCli, RunsExportedFromTheSimulatedStudyReproduceItsTables) {
  const auto root = temp("clearshape_cli_study_recordings");
  std::filesystem::remove_all(root);
  const std::string proto = protocol().string();
  const auto sim = run_cli("study " + proto + " --quick --out " + (root / "sim").string());
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const json a = read_json(root / "sim" / "results.json");
  EXPECT_EQ(a.at("rig").at("kind"), "simulated-thesis");
  EXPECT_TRUE(a.at("skipped_stages").empty());

  const auto tmpl = run_cli("study " + proto + " --quick --print-manifest");
  ASSERT_EQ(tmpl.exit_code, 0) << tmpl.err;
  EXPECT_NE(tmpl.out.find("id = \"unshaped/step-20/r03\""), std::string::npos);
  EXPECT_NE(tmpl.out.find("id = \"rig/B.1/zvdd@drive-model/r01\""), std::string::npos) << tmpl.out;

  // 1. Exact replay: the study's runs/*.csv with the template as it stands.
  const auto rec = root / "rec";
  std::filesystem::create_directories(rec);
  for (const auto& e : std::filesystem::directory_iterator(root / "sim" / "runs")) {
    if (e.path().extension() == ".csv") std::filesystem::copy_file(e.path(), rec / e.path().filename());
  }
  write_text(rec / "manifest.toml", tmpl.out);
  const auto replay = run_cli("study " + proto + " --quick --recordings " + rec.string() + " --out " +
                              (root / "replay").string());
  ASSERT_EQ(replay.exit_code, 0) << replay.err;
  const json b = read_json(root / "replay" / "results.json");
  EXPECT_EQ(b.at("rig").at("kind"), "recordings");
  EXPECT_TRUE(b.at("skipped_stages").empty());
  // The same records give the same numbers, bit for bit; only the rig tables' notes say what the
  // trials were (simulated predictions there, recorded measurements here).
  EXPECT_EQ(without_notes(a.at("tables")), without_notes(b.at("tables")));
  EXPECT_NE(table(b, "B.1").at("note").get<std::string>().find("Trials measured on the recorded rig"), std::string::npos);
  EXPECT_NE(table(a, "B.1").at("note").get<std::string>().find("Trials on the simulated rig"), std::string::npos);
  EXPECT_EQ(a.at("sections").at("clearance"), b.at("sections").at("clearance"));

  // 2. Renamed columns, commands in rad, encoder in counts, gyro in rad/s: within the trials' spread.
  const auto conv = root / "converted";
  std::filesystem::create_directories(conv);
  for (const auto& e : std::filesystem::directory_iterator(rec)) {
    if (e.path().extension() == ".csv") convert_run(e.path(), conv / e.path().filename());
  }
  write_text(conv / "manifest.toml",
             edit_manifest(tmpl.out,
                           "[columns]\ntime = \"t\"\ncommand = \"cmd_rad\"\ncommand_applied = \"drive_rad\"\n"
                           "command_unit = \"rad\"\nmotor_angle = \"enc\"\n"
                           "motor_angle_unit = \"counts\"\ncounts_per_rev = 12000\nlink_rate = \"gyro_rad_s\"\n"
                           "link_rate_unit = \"rad/s\"\n",
                           ""));
  const auto units = run_cli("study " + proto + " --quick --recordings " + conv.string() + " --out " +
                             (root / "units").string());
  ASSERT_EQ(units.exit_code, 0) << units.err;
  const json c = read_json(root / "units" / "results.json");
  int compared = 0;
  for (const auto& ta : a.at("tables")) {
    if (ta.at("kind") != "mean-deviation") continue;
    const json& tc = table(c, ta.at("id"));
    for (std::size_t j = 0; j < ta.at("columns").size(); ++j) {
      if (!ta["columns"][j].contains("ours_std")) continue;  // the trial tables (B.1–B.5)
      const double ma = ta["columns"][j].at("ours_mean");
      const double sa = ta["columns"][j].at("ours_std");
      const double mc = tc["columns"][j].at("ours_mean");
      EXPECT_LE(std::abs(mc - ma), sa) << ta.at("id") << " column " << j;
      ++compared;
    }
  }
  EXPECT_GE(compared, 10);

  // 3. A run missing: the stages needing it are skipped by name, on stderr and in results.json.
  const auto part = root / "partial";
  std::filesystem::create_directories(part);
  for (const auto& e : std::filesystem::directory_iterator(rec)) std::filesystem::copy_file(e.path(), part / e.path().filename());
  write_text(part / "manifest.toml", edit_manifest(tmpl.out, "", "unshaped/double-step-16/r02"));
  const auto missing = run_cli("study " + proto + " --quick --recordings " + part.string() + " --out " +
                               (root / "partial-out").string());
  ASSERT_EQ(missing.exit_code, 0) << missing.err;
  EXPECT_NE(missing.err.find("stage identification SKIPPED"), std::string::npos) << missing.err;
  EXPECT_NE(missing.err.find("unshaped/double-step-16/r02"), std::string::npos);
  const json d = read_json(root / "partial-out" / "results.json");
  ASSERT_GE(d.at("skipped_stages").size(), 2u);
  EXPECT_EQ(d["skipped_stages"][0].at("stage"), "consistency");
  EXPECT_EQ(d["skipped_stages"][1].at("stage"), "identification");
  EXPECT_EQ(d["skipped_stages"][1].at("missing_runs")[0], "unshaped/double-step-16/r02");
  std::filesystem::remove_all(root);
}

TEST(StudyRecordingsCli, BadManifestIsExitTwoWithFileLineAndKey) {
  const auto dir = temp("clearshape_cli_study_recordings_bad");
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  write_text(dir / "a.csv", "time_s,command_deg\n0,0\n");
  write_text(dir / "manifest.toml",
             "format = \"clearshape-recordings/1\"\n[[run]]\nid = \"unshaped/no-such-input/r01\"\nfile = \"a.csv\"\n");
  const std::string proto = protocol().string();
  auto r = run_cli("study " + proto + " --quick --recordings " + dir.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("manifest.toml:3"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--print-manifest"), std::string::npos) << r.err;
  write_text(dir / "manifest.toml",
             "format = \"clearshape-recordings/1\"\n[columns]\nlink_rate_unit = \"rpm\"\n");
  r = run_cli("study " + proto + " --quick --recordings " + dir.string());
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("columns.link_rate_unit"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("deg/s, rad/s, lsb"), std::string::npos) << r.err;
  EXPECT_EQ(run_cli("study " + proto + " --recordings " + (dir / "nothing").string()).exit_code, 2);
  std::filesystem::remove_all(dir);
}
