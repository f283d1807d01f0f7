// `clearshape recommend` on printer data: Klipper's smoothing and max acceleration per candidate
// in the table and the JSON, only for Klipper inputs (recomputed here from the JSON's impulses by
// Klipper's definition, written out independently of advise/smoothing.cpp, whose values are
// checked against Klipper's own code in tests/advise/test_smoothing.cpp); --weigh-smoothing
// klipper; bad values exit 2 naming the option.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include <nlohmann/json.hpp>

#include "support/cli.hpp"
#include "support/paths.hpp"

using clearshape::testing::golden_path;
using clearshape::testing::run_cli;

namespace {

std::string klipper_raw() { return golden_path("recommend_klipper_raw.csv").string(); }

nlohmann::json json_of(const std::string& args) {
  const auto r = run_cli("recommend " + args + " --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  return nlohmann::json::parse(r.out);
}

// Klipper's smoothing (docs/Measuring_Resonances.md, "max_smoothing"; shaper_calibrate.py): the
// larger of the 90° corner offset √2·Σ_{t≥t_s} A(v_sc + a/2·Δt)Δt and the 180° one Σ A·a/2·Δt².
double smoothing(const nlohmann::json& impulses, double accel, double scv) {
  double ts = 0.0, sum = 0.0;
  for (const auto& i : impulses) {
    ts += i["amplitude"].get<double>() * i["time_s"].get<double>();
    sum += i["amplitude"].get<double>();
  }
  ts /= sum;
  double o90 = 0.0, o180 = 0.0;
  for (const auto& i : impulses) {
    const double a = i["amplitude"].get<double>() / sum, dt = i["time_s"].get<double>() - ts;
    if (dt >= 0.0) o90 += a * (scv + 0.5 * accel * dt) * dt;
    o180 += a * 0.5 * accel * dt * dt;
  }
  return std::max(std::sqrt(2.0) * o90, o180);
}

}  // namespace

TEST(RecommendPrinterCli, KlipperInputShowsSmoothingAndMaxAccel) {
  const auto j = json_of("--data " + klipper_raw());
  ASSERT_TRUE(j["scoring"].contains("smoothing"));
  EXPECT_EQ(j["scoring"]["smoothing"]["weighed"], "none");
  for (const auto& c : j["candidates"]) {
    if (!c["available"].get<bool>()) continue;
    const double s = c["smoothing_mm"];
    EXPECT_NEAR(s, smoothing(c["impulses"], 5000.0, 5.0), 1e-9 * s) << c["name"];
    const double a = c["max_accel_mm_s2"];
    EXPECT_NEAR(smoothing(c["impulses"], a, 5.0), 0.12, 1e-9) << c["name"];  // the acceleration at the target
  }
  EXPECT_TRUE(j["recommendation"].contains("max_accel_mm_s2"));
  const auto t = run_cli("recommend --data " + klipper_raw());
  ASSERT_EQ(t.exit_code, 0) << t.err;
  EXPECT_NE(t.out.find("smoothing_mm"), std::string::npos) << t.out;
  EXPECT_NE(t.out.find("max_accel_mm_s2"), std::string::npos) << t.out;
}

TEST(RecommendPrinterCli, AGyroTableHasNoPrinterFigures) {
  const auto j = json_of("--data " + golden_path("recommend_one_mode.csv").string() + " --column gyro_deg_s --candidates zv,mzv");
  EXPECT_FALSE(j["scoring"].contains("smoothing"));
  EXPECT_FALSE(j["candidates"][0].contains("smoothing_mm"));
}

TEST(RecommendPrinterCli, WeighSmoothingKlipperPicksByTheScore) {
  const auto j = json_of("--data " + klipper_raw() + " --weigh-smoothing klipper --square-corner-velocity 8");
  EXPECT_EQ(j["scoring"]["smoothing"]["weighed"], "klipper");
  EXPECT_EQ(j["scoring"]["smoothing"]["square_corner_velocity_mm_s"], 8.0);
  EXPECT_NE(j["reason"].get<std::string>().find("Klipper's pick"), std::string::npos) << j["reason"];
  const std::string pick = j["recommendation"]["name"];
  for (const auto& c : j["candidates"]) {
    if (c["name"] == pick) {
      EXPECT_NEAR(c["smoothing_mm"].get<double>(), smoothing(c["impulses"], 5000.0, 8.0), 1e-9);
    }
  }
}

TEST(RecommendPrinterCli, BadPrinterOptionsAreExit2NamingTheOption) {
  const auto w = run_cli("recommend --data " + klipper_raw() + " --weigh-smoothing printer");
  EXPECT_EQ(w.exit_code, 2);
  EXPECT_NE(w.err.find("--weigh-smoothing"), std::string::npos) << w.err;
  const auto v = run_cli("recommend --data " + klipper_raw() + " --square-corner-velocity -1");
  EXPECT_EQ(v.exit_code, 2);
  EXPECT_NE(v.err.find("--square-corner-velocity"), std::string::npos) << v.err;
  const auto a = run_cli("recommend --data " + klipper_raw() + " --smoothing-accel 0");
  EXPECT_EQ(a.exit_code, 2);
  EXPECT_NE(a.err.find("--smoothing-accel"), std::string::npos) << a.err;
}
