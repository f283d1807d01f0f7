// What `recommend --plot` draws beyond the spectrum (docs/recommend.md, "The figure"): the PSD the
// recommended shaper leaves, P·V², against the NumPy golden (tests/golden/gen_after_shaper.py); the
// PSD's unit from the input; a Klipper file's X, Y, Z and sum; why a design frequency sits away
// from its mode (advise::DesignOffset).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "clearshape/advise/recommend.hpp"
#include "clearshape/advise/remaining.hpp"
#include "clearshape/advise/spectrum_input.hpp"
#include "clearshape/shaping/design.hpp"
#include "golden_support.hpp"
#include "support/paths.hpp"

namespace ad = clearshape::advise;
namespace sh = clearshape::shaping;

namespace {

nlohmann::json after_shaper_golden() {
  std::ifstream in(clearshape::testing::golden_path("after_shaper_reference.json"));
  return nlohmann::json::parse(in);
}

// A PSD of Lorentzian lines (f0, ζ, peak) on a 0.05 Hz grid.
ad::MeasuredSpectrum lines(const std::vector<std::array<double, 3>>& l) {
  ad::MeasuredSpectrum s;
  for (int k = 0; k <= 1600; ++k) {
    const double f = 0.05 * k;
    double p = 1e-4;
    for (const auto& [f0, zeta, peak] : l) p += peak / (1.0 + std::pow((f - f0) / (zeta * f0), 2));
    s.frequency_hz.push_back(f);
    s.power.push_back(p);
  }
  s.resolution_hz = 0.05;
  return s;
}

ad::ModeEstimate mode(double f_hz, double f_std_hz, double zeta) {
  ad::ModeEstimate m;
  m.frequency_hz = f_hz;
  m.frequency_std_hz = f_std_hz;
  m.damping_ratio = zeta;
  m.damping_ratio_std = 0.1 * zeta;
  return m;
}

std::filesystem::path temp_file(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / ("clearshape_after_shaper_" + name);
  std::ofstream(p) << text;
  return p;
}

}  // namespace

TEST(AfterShaper, PowerTimesVSquaredEqualsTheNumpyGolden) {
  const auto doc = after_shaper_golden();
  const std::vector<double> f = doc["frequency_hz"], p = doc["power"];
  ASSERT_EQ(doc["cases"].size(), 3u);
  for (const auto& c : doc["cases"]) {
    std::vector<sh::Impulse> imp;
    for (std::size_t i = 0; i < c["impulse_times_s"].size(); ++i) imp.push_back({c["impulse_times_s"][i], c["impulse_amplitudes"][i]});
    // The library's ZV/ZVD are the same closed forms as the golden's.
    sh::DesignRequest r;
    r.method = sh::method_from_string(c["shaper"].get<std::string>());
    r.mode = sh::Mode::from_hz(c["design_frequency_hz"], c["design_damping"]);
    const sh::Shaper designed = sh::design(r);
    ASSERT_EQ(designed.size(), imp.size());
    for (std::size_t i = 0; i < imp.size(); ++i) {
      EXPECT_NEAR(designed.impulses()[i].time_s, imp[i].time_s, 1e-12);
      EXPECT_NEAR(designed.impulses()[i].amplitude, imp[i].amplitude, 1e-12);
    }
    const std::vector<double> after = ad::power_after_shaper(designed, f, p, c["test_damping_ratios"], c["frequency_scales"]);
    const std::vector<double> want = c["after_shaper"];
    for (std::size_t k = 0; k < f.size(); ++k) {
      ASSERT_NEAR(after[k], want[k], 1e-10 * p[k] + 1e-15) << c["shaper"] << " at " << f[k] << " Hz";
    }
  }
}

TEST(AfterShaper, RefusesMismatchedLengths) {
  sh::DesignRequest r;
  r.method = sh::Method::zv;
  r.mode = sh::Mode::from_hz(10.0, 0.1);
  const sh::Shaper zv = sh::design(r);
  EXPECT_THROW(ad::power_after_shaper(zv, {1.0, 2.0}, {1.0}, {0.1}, {1.0}), clearshape::InvalidArgument);
}

TEST(AfterShaper, PsdUnitFromTheColumnsUnitSuffix) {
  EXPECT_EQ(ad::psd_unit_of_column("gyro_deg_s"), "(deg/s)²/Hz");
  EXPECT_EQ(ad::psd_unit_of_column("link_rate_rad_s"), "(rad/s)²/Hz");
  EXPECT_EQ(ad::psd_unit_of_column("accel_m_s2"), "(m/s²)²/Hz");
  EXPECT_EQ(ad::psd_unit_of_column("accel_mm_s2"), "(mm/s²)²/Hz");
  EXPECT_EQ(ad::psd_unit_of_column("motor_deg"), "deg²/Hz");
  EXPECT_EQ(ad::psd_unit_of_column("input_V"), "V²/Hz");
  EXPECT_EQ(ad::psd_unit_of_column("torque_n_m"), "(N·m)²/Hz");
  EXPECT_EQ(ad::psd_unit_of_column("accel"), "(unit of accel)²/Hz");
  EXPECT_EQ(ad::psd_unit_of_column("col2"), "(unit of col2)²/Hz");
}

TEST(AfterShaper, KlipperPsdFileCarriesItsUnitAndEveryAxis) {
  const ad::MeasuredSpectrum s = advise_test::load("recommend_klipper_raw_psd.csv", "psd_y");
  EXPECT_EQ(s.power_unit, "(mm/s²)²/Hz");
  ASSERT_EQ(s.axes.size(), 4u);
  EXPECT_EQ(s.axes[0].column, "psd_x");
  EXPECT_EQ(s.axes[3].column, "psd_xyz");
  EXPECT_EQ(s.axes[1].power, s.power);  // the analysed column is psd_y
  // calibrate_shaper's files with shaper columns hold the PSD ÷ (f + 0.1 Hz).
  const auto p = temp_file("normalized.csv", "freq,psd_x,psd_y,psd_z,psd_xyz,shapers:,zv\n5,1,2,3,6,,0.5\n5.2,1,2,3,6,,0.5\n5.4,1,2,3,6,,0.5\n");
  ad::SpectrumRequest r;
  r.path = p;
  EXPECT_EQ(ad::load_spectrum(r).power_unit, "(mm/s²)²/Hz²");
  std::filesystem::remove(p);
}

TEST(AfterShaper, KlipperRawFileCarriesTheThreeAxesAndTheirSum) {
  const ad::MeasuredSpectrum s = advise_test::load("recommend_klipper_raw.csv", "accel_x");
  EXPECT_EQ(s.power_unit, "(mm/s²)²/Hz");
  ASSERT_EQ(s.axes.size(), 4u);
  EXPECT_EQ(s.axes[0].power, s.power);
  const ad::MeasuredSpectrum sum = advise_test::load("recommend_klipper_raw.csv", "xyz");
  for (std::size_t k = 0; k < s.power.size(); ++k) {
    ASSERT_NEAR(s.axes[3].power[k], s.axes[0].power[k] + s.axes[1].power[k] + s.axes[2].power[k], 1e-12 * s.axes[3].power[k]);
    ASSERT_DOUBLE_EQ(sum.power[k], s.axes[3].power[k]);
  }
}

TEST(AfterShaper, TableCarriesItsColumnsUnit) {
  EXPECT_EQ(advise_test::load("recommend_one_mode.csv", "gyro_deg_s").power_unit, "(deg/s)²/Hz");
}

TEST(DesignOffset, NoneWhenTheDesignIsWithinOneSigmaOfALoneLine) {
  // One clean line at 20 Hz, known to 2 %: the delay rule's MZV lands within 1σ.
  const ad::MeasuredSpectrum s = lines({{{20.0, 0.05, 1.0}}});
  ad::RecommendOptions o;
  o.candidates = {"mzv"};
  const ad::Recommendation r = ad::recommend({s}, {mode(20.0, 0.4, 0.05)}, o);
  ASSERT_TRUE(r.chosen);
  EXPECT_LE(std::abs(r.candidates[*r.chosen].design_frequency_hz[0] - 20.0), 0.4);
  EXPECT_TRUE(r.design_offsets.empty());
}

TEST(DesignOffset, ALineTheModesMissPullsTheDesignAndSaysSo) {
  // A second line at 25 Hz that the modes do not hold: the spectrum pulls MZV above the 20 Hz mode.
  const ad::MeasuredSpectrum s = lines({{{20.0, 0.05, 1.0}}, {{25.0, 0.05, 0.6}}});
  ad::RecommendOptions o;
  o.candidates = {"mzv"};
  const ad::Recommendation r = ad::recommend({s}, {mode(20.0, 0.05, 0.05)}, o);
  ASSERT_TRUE(r.chosen);
  ASSERT_EQ(r.design_offsets.size(), 1u);
  const ad::DesignOffset& d = r.design_offsets[0];
  EXPECT_GT(d.design_frequency_hz, 21.0);
  EXPECT_EQ(d.cause, "spectrum");
  EXPECT_GT(d.spectrum_hz, 0.5) << d.reason;
  EXPECT_NEAR(d.offset_sigmas, (d.design_frequency_hz - 20.0) / 0.05, 1e-9);
  EXPECT_NEAR(d.spectrum_hz + d.near_best_hz + d.worst_case_hz + d.selection_hz, d.design_frequency_hz - 20.0, 1e-9);
  EXPECT_NE(d.reason.find("not centred on the mode's line"), std::string::npos) << d.reason;
  EXPECT_NE(d.reason.find("MZV at"), std::string::npos) << d.reason;
}

TEST(DesignOffset, AWideDampingBandMovesTheDesignForTheWorstCase) {
  // A lone line, its ζ tested over 0.02–0.3: the worst case, not the spectrum, moves ZV.
  const ad::MeasuredSpectrum s = lines({{{20.0, 0.05, 1.0}}});
  ad::RecommendOptions o;
  o.candidates = {"zv"};
  o.damping_low = 0.02;
  o.damping_high = 0.3;
  o.design_damping = 0.05;
  const ad::Recommendation r = ad::recommend({s}, {mode(20.0, 0.05, 0.05)}, o);
  ASSERT_TRUE(r.chosen);
  ASSERT_EQ(r.design_offsets.size(), 1u) << r.candidates[0].design_frequency_hz[0];
  const ad::DesignOffset& d = r.design_offsets[0];
  EXPECT_EQ(d.cause, "worst_case") << d.reason;
  EXPECT_LT(2.0 * std::abs(d.spectrum_hz), std::abs(d.worst_case_hz)) << d.reason;
  EXPECT_NE(d.reason.find("for the worst case over ζ 0.02–0.3"), std::string::npos) << d.reason;
}
