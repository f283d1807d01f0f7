// `recommend --plot` (docs/recommend.md, "The figure"): the figure's data (study::recommend_plot_data)
// carries the PSD's unit, a Klipper file's X, Y, Z and sum, the PSD the pick leaves (P·V², V the
// curve drawn for the pick) and why a design frequency sits away from its mode; the script draws
// them with the same bytes every time.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <unistd.h>

#include <nlohmann/json.hpp>

#include "clearshape/study/recommend_report.hpp"
#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::golden_path;
using clearshape::testing::read_bytes;
using clearshape::testing::run_cli;
namespace st = clearshape::study;

namespace {

std::filesystem::path temp(const std::string& name) {
  return std::filesystem::temp_directory_path() / ("recommend_plot_" + std::to_string(::getpid()) + "_" + name);
}

nlohmann::ordered_json plot_data(const std::string& file, const std::string& column) {
  st::RecommendRequest q;
  clearshape::advise::SpectrumRequest s;
  s.path = golden_path(file);
  s.column = column;
  q.data = {s};
  return st::recommend_plot_data(st::recommend(q));
}

int run_script(const std::filesystem::path& data, const std::filesystem::path& png) {
  const auto script = golden_path("").parent_path().parent_path().parent_path() / "python" / "plot_recommend.py";
  return std::system(("/usr/bin/python3 " + script.string() + " " + data.string() + " " + png.string()).c_str());
}

}  // namespace

TEST(RecommendPlot, KlipperPsdDataHasTheUnitTheAxesAndTheAfterShaperCurve) {
  const auto d = plot_data("recommend_klipper_raw_psd.csv", "psd_xyz");
  ASSERT_EQ(d["spectra"].size(), 1u);
  const auto& s = d["spectra"][0];
  EXPECT_EQ(s["power_unit"], "(mm/s²)²/Hz");
  ASSERT_EQ(s["axes"].size(), 4u);
  EXPECT_EQ(s["axes"][0]["column"], "psd_x");
  EXPECT_EQ(s["axes"][3]["power"], s["power"]);  // psd_xyz is analysed
  // After the shaper: P × V², V the recommended candidate's curve (evaluated on the spectrum's bins here).
  const nlohmann::ordered_json* chosen = nullptr;
  for (const auto& c : d["candidates"]) {
    if (c["chosen"].get<bool>()) chosen = &c;
  }
  ASSERT_NE(chosen, nullptr);
  const std::vector<double> p = s["power"], after = s["power_after_shaper"], f = s["frequency_hz"];
  ASSERT_EQ(after.size(), p.size());
  double before_sum = 0.0, after_sum = 0.0;
  for (std::size_t k = 0; k < p.size(); ++k) {
    ASSERT_LE(after[k], p[k] * (1.0 + 1e-12));  // V ≤ 1 for a positive shaper
    before_sum += p[k];
    after_sum += after[k];
  }
  EXPECT_LT(after_sum, 0.2 * before_sum);  // MZV at the 42 Hz mode removes most of it
  EXPECT_TRUE(d["design_offsets"].is_array());
}

TEST(RecommendPlot, ATableCarriesItsColumnsUnitAndTheOffsetReason) {
  // The simulated run: MZV lands 9σ below the fitted mode; the data say why.
  const auto d = plot_data("recommend_sim_run.csv", "gyro_deg_s");
  EXPECT_EQ(d["spectra"][0]["power_unit"], "(deg/s)²/Hz");
  EXPECT_TRUE(d["spectra"][0]["axes"].empty());
  ASSERT_EQ(d["design_offsets"].size(), 1u);
  const auto& o = d["design_offsets"][0];
  EXPECT_EQ(o["cause"], "spectrum");
  EXPECT_GT(std::abs(o["offset_sigmas"].get<double>()), 1.0);
  const double parts = o["spectrum_hz"].get<double>() + o["near_best_hz"].get<double>() + o["worst_case_hz"].get<double>() +
                       o["selection_hz"].get<double>();
  EXPECT_NEAR(parts, o["design_frequency_hz"].get<double>() - o["mode_frequency_hz"].get<double>(), 1e-9);
  EXPECT_NE(o["reason"].get<std::string>().find("MZV at"), std::string::npos);
}

TEST(RecommendPlot, TheScriptDrawsTheSameBytesEveryTime) {
  const auto data = temp("data.json"), a = temp("a.png"), b = temp("b.png");
  std::ofstream(data) << plot_data("recommend_sim_run.csv", "gyro_deg_s").dump();
  ASSERT_EQ(run_script(data, a), 0);
  ASSERT_EQ(run_script(data, b), 0);
  const std::string pa = read_bytes(a);
  ASSERT_GT(pa.size(), 1000u);
  EXPECT_TRUE(pa == read_bytes(b));
  for (const auto& p : {data, a, b}) std::filesystem::remove(p);
}

TEST(RecommendPlot, KlipperPlotThroughTheCliIsDeterministic) {
  const auto a = temp("k1.png"), b = temp("k2.png");
  const std::string args = "recommend --data " + golden_path("recommend_klipper_raw_psd.csv").string() + " --candidates zv,mzv,ei";
  ASSERT_EQ(run_cli(args + " --plot " + a.string()).exit_code, 0);
  ASSERT_EQ(run_cli(args + " --plot " + b.string()).exit_code, 0);
  const std::string pa = read_bytes(a);
  EXPECT_EQ(pa.substr(1, 3), "PNG");
  EXPECT_TRUE(pa == read_bytes(b)) << "the PNG differs between two identical runs";
  std::filesystem::remove(a);
  std::filesystem::remove(b);
}
