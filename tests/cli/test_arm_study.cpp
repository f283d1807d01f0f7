// clearshape arm study: the quick study end to end (results.json and tables.md in --out, the
// table on stdout), refusals (exit 2 naming the file and key), and python/render_arm_study.py on
// its output: three figures, a self-contained report.html with them embedded, the same bytes on a
// second rendering, and a folder without results.json refused (exit 2).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

namespace {

clearshape::testing::CliResult render(const fs::path& dir) {
  const fs::path script = clearshape::testing::studies_path("").parent_path().parent_path() / "python" /
                          "render_arm_study.py";
  return clearshape::testing::run_shell("/usr/bin/python3 '" + script.string() + "' '" + dir.string() + "'");
}

std::string bytes(const fs::path& p) { return clearshape::testing::read_bytes(p); }

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

}  // namespace

TEST(ArmStudyCli, QuickStudyWritesResultsAndItsReportRenders) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_study_cli");
  const auto study = clearshape::testing::studies_path("arm-scara2.toml");
  const auto r = run_cli("arm study '" + study.string() + "' --out '" + dir.string() + "' --quick");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("clearance-aware"), std::string::npos) << r.out;
  std::ifstream in(dir / "results.json");
  const auto doc = nlohmann::json::parse(in);
  EXPECT_TRUE(doc["study"]["quick"].get<bool>());
  EXPECT_EQ(doc["moves"].size(), 3u);
  EXPECT_EQ(doc["designs"].size(), 4u);
  EXPECT_NE(bytes(dir / "tables.md").find("| clearance-aware |"), std::string::npos);

  const auto first = render(dir);
  ASSERT_EQ(first.exit_code, 0) << first.err;
  const std::string html = bytes(dir / "report.html");
  EXPECT_EQ(count(html, "src=\"data:image/png;base64,"), 3u);
  EXPECT_EQ(count(html, "src=\"http"), 0u);  // self-contained
  EXPECT_NE(html.find("linearised"), std::string::npos);
  // Every design worse than unshaped on some move is named in the report, or none is.
  std::size_t worse_designs = 0;
  for (const auto& d : doc["designs"]) worse_designs += d["moves_worse_than_unshaped"].get<int>() > 0 ? 1 : 0;
  EXPECT_EQ(count(html, " moves (move "), worse_designs) << html.substr(0, 3000);
  if (worse_designs == 0) {
    EXPECT_NE(html.find("No design is worse than unshaped"), std::string::npos);
  }
  const std::string png = bytes(dir / "figures" / "mode-map.png");
  ASSERT_EQ(render(dir).exit_code, 0);
  EXPECT_EQ(bytes(dir / "figures" / "mode-map.png"), png);
  EXPECT_EQ(bytes(dir / "report.html"), html);
}

TEST(ArmStudyCli, RefusesABadStudyAndAFolderWithoutResults) {
  const fs::path dir = clearshape::testing::fresh_temp_dir("arm_study_cli_bad");
  std::ofstream(dir / "bad.toml") << "[study]\narm = \"scara-2\"\n[benchmark]\nmoves = 3\n";
  const auto r = run_cli("arm study '" + (dir / "bad.toml").string() + "' --out '" + (dir / "out").string() + "'");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("bad.toml"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("benchmark.moves"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("20 … 1000"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(dir / "out" / "results.json"));
  const auto empty = render(dir);
  EXPECT_EQ(empty.exit_code, 2) << empty.err;
  EXPECT_NE(empty.err.find("results.json"), std::string::npos) << empty.err;
}
