// Eq. 5.1 with the band-entry start rule against an independent NumPy implementation
// (tests/golden/gen_mean_deviation.py): ringing, one-sided approaches with drift, noise below
// and above the band, a two-step (ZV-like) response, and the options.
#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>

#include "clearshape/io/table.hpp"
#include "clearshape/metrics/mean_deviation.hpp"
#include "support/paths.hpp"

namespace cs = clearshape;
namespace m = clearshape::metrics;

TEST(MeanDeviationGolden, BandAndCrossingCases) {
  const auto table = cs::io::read_table(cs::testing::golden_path("mean_deviation_signals.csv"));
  nlohmann::json golden;
  std::ifstream(cs::testing::golden_path("mean_deviation_expected.json")) >> golden;
  int band_cases = 0;
  int crossing_cases = 0;
  for (const auto& c : golden["cases"]) {
    SCOPED_TRACE(c.dump());
    m::MeanDeviationOptions options;
    const auto& o = c["options"];
    if (o.contains("search_from_s")) options.search_from_s = o["search_from_s"].get<double>();
    if (o.contains("band_noise_multiple")) options.band_noise_multiple = o["band_noise_multiple"].get<double>();
    if (o.contains("band_move_fraction")) options.band_move_fraction = o["band_move_fraction"].get<double>();
    if (o.contains("band_dwell_s")) options.band_dwell_s = o["band_dwell_s"].get<double>();
    if (o.contains("band_half_width")) options.band_half_width = o["band_half_width"].get<double>();
    const auto r = m::mean_deviation(
        cs::io::series_from_table(table, "time_s", c["signal"].get<std::string>()), options);
    const auto& e = c["expected"];
    // Indices and the rule exactly; values to 1e-12 (the CSV carries 17 significant digits; the
    // two sides sum in different orders).
    EXPECT_EQ(std::string(m::to_string(r.start_rule)), e["start_rule"].get<std::string>());
    EXPECT_EQ(r.start_index, e["start_index"].get<std::size_t>());
    EXPECT_EQ(r.iterations, e["iterations"].get<int>());
    EXPECT_EQ(r.converged, e["converged"].get<bool>());
    EXPECT_NEAR(r.band_half_width, e["band_half_width"].get<double>(), 1e-12);
    EXPECT_NEAR(r.noise_floor, e["noise_floor"].get<double>(), 1e-12);
    EXPECT_NEAR(r.steady_mean, e["steady_mean"].get<double>(), 1e-12);
    EXPECT_NEAR(r.mean_deviation, e["mean_deviation"].get<double>(), 1e-12);
    (r.start_rule == m::StartRule::band_entry ? band_cases : crossing_cases) += 1;
  }
  EXPECT_GE(band_cases, 3);  // the golden set exercises both rules
  EXPECT_GE(crossing_cases, 3);
}
