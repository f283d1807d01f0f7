// `clearshape modes` chooses its model order by a stabilisation diagram (issue 20): the same record
// gives the same frequencies for --modes 2, 3 and 4; the diagram is in --json and --diagram-csv.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/units.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::process_temp_path;
using clearshape::testing::run_cli;

namespace {

// Two modes (6.2 Hz ζ 0.03, 17.5 Hz ζ 0.012) + offset + white noise σ 2 (seed 7), 1 kHz, 2.5 s.
std::string write_decay() {
  const auto path = process_temp_path("modes_diagram_decay.csv");
  std::ofstream out(path);
  out << "time_s,rate_deg_s\n";
  std::mt19937_64 rng(7);
  std::normal_distribution<double> nd;
  const double modes[2][4] = {{6.2, 0.03, 40.0, 0.4}, {17.5, 0.012, 15.0, -1.0}};
  for (int k = 0; k < 2500; ++k) {
    const double t = k * 1e-3;
    double v = 0.3;
    for (const auto& m : modes) {
      const double wn = clearshape::kTwoPi * m[0];
      v += m[2] * std::exp(-m[1] * wn * t) * std::cos(wn * std::sqrt(1 - m[1] * m[1]) * t + m[3]);
    }
    out << fmt::format("{:.3f},{:.12g}\n", t, v + 2.0 * nd(rng));
  }
  return path.string();
}

}  // namespace

TEST(ModesDiagramCli, FrequencyDoesNotMoveWithModesAndTheDiagramIsReported) {
  const std::string data = write_decay();
  std::vector<double> f1, f2;
  for (int modes = 2; modes <= 4; ++modes) {
    const auto r = run_cli(fmt::format("modes --data {} --output-column rate_deg_s --modes {} --json", data, modes));
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const auto j = nlohmann::json::parse(r.out);
    EXPECT_EQ(j["order_source"], "stabilisation");
    ASSERT_EQ(j["modes"].size(), 2u);  // two persistent modes, whatever --modes asks
    f1.push_back(j["modes"][0]["frequency_hz"].get<double>());
    f2.push_back(j["modes"][1]["frequency_hz"].get<double>());
    const auto& s = j["stabilisation"];
    EXPECT_EQ(s["chosen_order"].get<std::size_t>(), j["order"].get<std::size_t>());
    ASSERT_EQ(s["persistent_modes"].size(), 2u);
    EXPECT_NEAR(s["persistent_modes"][0]["frequency_hz"].get<double>(), 6.2, 0.02);
    EXPECT_NEAR(s["persistent_modes"][1]["frequency_hz"].get<double>(), 17.5, 0.05);
    EXPECT_EQ(s["orders"].front()["order"], 2);
    EXPECT_EQ(s["orders"].back()["order"], 24);
    EXPECT_DOUBLE_EQ(s["tolerances"]["frequency_relative"].get<double>(), 0.01);
    EXPECT_DOUBLE_EQ(s["tolerances"]["damping_relative"].get<double>(), 0.05);
  }
  for (std::size_t i = 1; i < f1.size(); ++i) {
    EXPECT_NEAR(f1[i], f1[0], 0.005 * f1[0]);
    EXPECT_NEAR(f2[i], f2[0], 0.005 * f2[0]);
  }
  std::filesystem::remove(data);
}

TEST(ModesDiagramCli, DiagramCsvForPlotting) {
  const std::string data = write_decay();
  const auto csv = process_temp_path("modes_diagram.csv");
  const auto r = run_cli(fmt::format("modes --data {} --output-column rate_deg_s --modes 2 --diagram-csv {}", data, csv.string()));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("from the stabilisation diagram"), std::string::npos) << r.out;
  std::ifstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "order,frequency_hz,damping_ratio,amplitude,stable_frequency,stable_damping,stable");
  int rows = 0, stable = 0;
  while (std::getline(in, line)) {
    ++rows;
    stable += line.substr(line.rfind(',') + 1) == "1" ? 1 : 0;
  }
  EXPECT_GT(rows, 40);
  EXPECT_GE(stable, 30);  // both modes stable from order 5 to 24
  // A fixed --order has no diagram: no CSV to write (exit 2, naming the options).
  const auto fixed = run_cli(fmt::format("modes --data {} --output-column rate_deg_s --order 6 --diagram-csv {}", data, csv.string()));
  EXPECT_EQ(fixed.exit_code, 2) << fixed.err;
  EXPECT_NE(fixed.err.find("--diagram-csv"), std::string::npos) << fixed.err;
  std::filesystem::remove(csv);
  std::filesystem::remove(data);
}
