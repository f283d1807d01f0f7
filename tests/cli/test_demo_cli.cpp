#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "support/cli.hpp"

namespace fs = std::filesystem;
using clearshape::testing::run_cli;

TEST(DemoCli, ShapingRemovesTheDriveModelsOvershoot) {
  const fs::path dir =
      fs::temp_directory_path() / ("clearshape_demo_cli_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  const auto r = run_cli("demo --json --out " + dir.string());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  // The table goes first on stdout, then the JSON document.
  const auto brace = r.out.find('{');
  ASSERT_NE(brace, std::string::npos) << r.out;
  const auto doc = nlohmann::json::parse(r.out.substr(brace));
  ASSERT_EQ(doc["results"].size(), 4u);
  const auto& unshaped = doc["results"][0];
  EXPECT_EQ(unshaped["shaper"], "unshaped");
  // Eq. 4.2 speed model: 10.9 % overshoot unshaped (closed form, see examples/04).
  EXPECT_NEAR(unshaped["overshoot_percent"].get<double>(), 10.89, 0.05);
  for (std::size_t i = 1; i < 4; ++i) {
    const auto& shaped = doc["results"][i];
    // A shaper designed on the model's own mode leaves only the non-oscillatory real pole.
    EXPECT_LT(shaped["overshoot_percent"].get<double>(), 0.5) << shaped["shaper"];
    EXPECT_GT(shaped["delay_s"].get<double>(), doc["results"][i - 1]["delay_s"].get<double>());
  }
  const auto csv = clearshape::io::read_table(dir / "demo.csv");
  EXPECT_EQ(csv.names.front(), "time_s");
  EXPECT_TRUE(csv.find("speed_zvdd_deg_s").has_value());
  EXPECT_TRUE(fs::exists(dir / "demo.json"));
  fs::remove_all(dir);
}

TEST(DemoCli, RejectsABadRate) {
  const auto r = run_cli("demo --rate 0 --out /tmp/clearshape_demo_bad");
  EXPECT_EQ(r.exit_code, 2);
}

// Issue 21: `demo --out FILE` ran, printed its table, then exited 1 with a raw errno text
// ("cannot create folder: Not a directory"). Now --out is checked while parsing: exit 2 naming
// the option and the file, before any work, the file left as it was.
TEST(DemoCli, AnOutputFolderThatIsAFileIsRefusedByNameBeforeAnyWork) {
  const fs::path file = fs::temp_directory_path() / ("clearshape_demo_cli_file_" + std::to_string(::getpid()));
  { std::ofstream(file) << "keep\n"; }
  for (const fs::path& out : {file, file / "sub"}) {
    const auto r = run_cli("demo --out " + out.string());
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("--out: " + file.string() + " is a file, not a folder"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("give a folder (created if missing)"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("Not a directory"), std::string::npos) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  std::ifstream in(file);
  std::string kept;
  std::getline(in, kept);
  EXPECT_EQ(kept, "keep");
  fs::remove(file);
}
