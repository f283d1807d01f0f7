// --export json: parse it back; the taps are discretize()'s bit for bit, V is recomputed.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "clearshape/core/error.hpp"
#include "clearshape/export/export.hpp"
#include "clearshape/export/json_export.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"

namespace ex = clearshape::exports;
namespace sh = clearshape::shaping;

namespace {

ex::ShaperDesign design(sh::Method m, double f_hz, double zeta) {
  sh::DesignRequest r;
  r.method = m;
  r.mode = sh::Mode::from_hz(f_hz, zeta);
  return {sh::design(r), m, r.mode, std::nullopt, std::nullopt, std::nullopt, "clearshape shape ..."};
}

}  // namespace

TEST(JsonExport, TapsAreDiscretizesBitForBit) {
  const ex::ShaperDesign d = design(sh::Method::zvdd, 14.955, 0.07);
  ex::ExportOptions o;
  o.sample_time_s = 1e-3;
  const auto j = nlohmann::json::parse(ex::to_json(d, o).text);
  EXPECT_EQ(j["schema_version"], 2);
  EXPECT_TRUE(j.contains("clearshape_version"));
  EXPECT_EQ(j["design"]["method"], "zvdd");
  EXPECT_EQ(j["design"]["mode"]["frequency_hz"].get<double>(), 14.955);  // not 14.955000000000002
  EXPECT_EQ(j["design"]["mode"]["zeta"].get<double>(), 0.07);
  const auto taps = sh::discretize(d.shaper, 1e-3);
  ASSERT_EQ(j["discrete"]["taps"].size(), taps.size());
  for (std::size_t i = 0; i < taps.size(); ++i) {
    EXPECT_EQ(j["discrete"]["taps"][i]["delay_samples"].get<std::size_t>(), taps[i].delay_samples);
    EXPECT_EQ(j["discrete"]["taps"][i]["weight"].get<double>(), taps[i].weight);  // exact
  }
  EXPECT_EQ(j["discrete"]["history_samples"].get<std::size_t>(), sh::max_delay_samples(taps) + 1);
  ASSERT_EQ(j["impulses"].size(), d.shaper.size());
  EXPECT_EQ(j["impulses"][1]["time_s"].get<double>(), d.shaper.impulses()[1].time_s);
  // V of the taps as impulses at d·Ts, recomputed here from the parsed numbers.
  std::vector<sh::Impulse> imp;
  for (const auto& t : j["discrete"]["taps"]) imp.push_back({t["delay_samples"].get<double>() * 1e-3, t["weight"].get<double>()});
  const sh::Shaper discrete("taps", imp, sh::Shaper::Normalize::no);
  EXPECT_EQ(j["residual_vibration"]["at_design"]["discrete"].get<double>(), sh::residual_vibration(discrete, *d.mode));
  // The same from Eq. 2.19 written out here (Singer & Seering 1990): V = e^{−ζωn·t_N}·√(C² + S²)/ΣA,
  // C = Σ A_i e^{ζωn·t_i} cos(ωd·t_i), S = Σ A_i e^{ζωn·t_i} sin(ωd·t_i) — at every band point.
  for (const auto& point : j["residual_vibration"]["band"]["points"]) {
    const double wn = point["ratio"].get<double>() * d.mode->natural_frequency_rad_s;
    const double z = d.mode->damping_ratio;
    const double wd = wn * std::sqrt(1.0 - z * z);
    const double t_last = imp.back().time_s;
    double c = 0.0, s_ = 0.0, sum = 0.0;
    for (const sh::Impulse& p : imp) {
      c += p.amplitude * std::exp(z * wn * (p.time_s - t_last)) * std::cos(wd * p.time_s);
      s_ += p.amplitude * std::exp(z * wn * (p.time_s - t_last)) * std::sin(wd * p.time_s);
      sum += p.amplitude;
    }
    EXPECT_NEAR(point["discrete"].get<double>(), std::hypot(c, s_) / sum, 1e-12) << point["ratio"];
  }
  EXPECT_LT(j["residual_vibration"]["at_design"]["continuous"].get<double>(), 1e-12);
  EXPECT_GT(j["residual_vibration"]["at_design"]["discrete"].get<double>(), 1e-6);  // linear split: not zero
  ASSERT_EQ(j["residual_vibration"]["band"]["points"].size(), ex::kBandPoints);
  EXPECT_EQ(j["residual_vibration"]["band"]["points"][10]["ratio"].get<double>(), 1.0);
  EXPECT_EQ(j["units"]["time_s"], "s");
}

TEST(JsonExport, ExactDiscretisationLeavesNoVibrationAtTheMode) {
  const ex::ShaperDesign d = design(sh::Method::zvd, 13.7, 0.07);
  ex::ExportOptions o;
  o.sample_time_s = 2e-3;
  o.discretization = sh::Discretization::exact_at_mode;
  const auto j = nlohmann::json::parse(ex::to_json(d, o).text);
  EXPECT_EQ(j["discrete"]["discretization"], "exact");
  EXPECT_LT(j["residual_vibration"]["at_design"]["discrete"].get<double>(), 1e-12);
}

TEST(JsonExport, CustomWithoutModeHasNoResidual) {
  ex::ShaperDesign d{sh::Shaper("custom", {{0.0, 0.5}, {0.0105, 0.5}}), sh::Method::custom, {}, {}, {}, {}, ""};
  ex::ExportOptions o;
  o.sample_time_s = 1e-3;
  const auto j = nlohmann::json::parse(ex::to_json(d, o).text);
  EXPECT_TRUE(j["residual_vibration"].is_null());
  EXPECT_FALSE(j["design"].contains("mode"));
  ASSERT_EQ(j["discrete"]["taps"].size(), 3u);  // 0.5 at 0, 0.5 split over samples 10 and 11
  EXPECT_EQ(j["discrete"]["taps"][1]["delay_samples"], 10);
}

TEST(JsonExport, RejectsABadSampleTime) {
  const ex::ShaperDesign d = design(sh::Method::zv, 10.0, 0.1);
  ex::ExportOptions o;
  for (double ts : {0.0, -1e-3, std::nan("")}) {
    o.sample_time_s = ts;
    EXPECT_THROW(ex::to_json(d, o), clearshape::InvalidArgument) << ts;
  }
  EXPECT_THROW(ex::format_from_string("yaml"), clearshape::InvalidArgument);
  try {
    ex::format_from_string("yaml");
  } catch (const clearshape::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("json, c-header, klipper, rrf"), std::string::npos) << e.what();
  }
}
