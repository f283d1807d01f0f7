// advise::load_spectrum: each input format against SciPy's Welch PSD of the same recording
// (tests/golden/gen_recommend.py), and every error naming file, line and field.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <unistd.h>

#include "clearshape/advise/spectrum_input.hpp"
#include "clearshape/core/error.hpp"
#include "golden_support.hpp"

namespace ad = clearshape::advise;
using advise_test::load;

namespace {

// Every bin of `psd_file`'s column (≤ 200 Hz) against the spectrum, relative to its maximum.
void expect_same_psd(const ad::MeasuredSpectrum& s, const std::string& psd_file, const std::string& column) {
  const ad::MeasuredSpectrum g = load(psd_file, column);
  ASSERT_EQ(g.format, ad::InputFormat::klipper_psd);
  ASSERT_LE(g.frequency_hz.size(), s.frequency_hz.size());
  double peak = 0.0;
  for (const double p : g.power) peak = std::max(peak, p);
  for (std::size_t k = 0; k < g.frequency_hz.size(); ++k) {
    ASSERT_NEAR(s.frequency_hz[k], g.frequency_hz[k], 1e-9 * (1.0 + g.frequency_hz[k])) << k;
    ASSERT_NEAR(s.power[k], g.power[k], 1e-9 * peak) << psd_file << " bin " << k;
  }
}

std::filesystem::path write_temp(const std::string& name, const std::string& text) {
  const auto p = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::ofstream(p) << text;
  return p;
}

std::string error_of(const std::string& name, const std::string& text, const std::string& column) {
  ad::SpectrumRequest r;
  r.path = write_temp(name, text);
  r.column = column;
  try {
    (void)ad::load_spectrum(r);
  } catch (const clearshape::InputError& e) {
    std::filesystem::remove(r.path);
    return e.what();
  }
  std::filesystem::remove(r.path);
  return "no error";
}

}  // namespace

TEST(SpectrumInput, DetectsTheFormatFromTheFirstLine) {
  EXPECT_EQ(ad::detect_format("#time,accel_x,accel_y,accel_z\n1,2,3,4\n"), ad::InputFormat::klipper_raw);
  EXPECT_EQ(ad::detect_format("\n freq,psd_x,psd_y,psd_z,psd_xyz,shapers:,zv(40.0)\n"), ad::InputFormat::klipper_psd);
  EXPECT_EQ(ad::detect_format("time_s,gyro_deg_s\n0,1\n"), ad::InputFormat::table);
}

TEST(SpectrumInput, TableWelchMatchesScipy) {
  const ad::MeasuredSpectrum s = load("recommend_one_mode.csv", "gyro_deg_s");
  EXPECT_EQ(s.format, ad::InputFormat::table);
  const auto& w = advise_test::klipper_case("one_mode")["welch"];
  EXPECT_EQ(s.segments, w["segments"].get<std::size_t>());
  EXPECT_DOUBLE_EQ(s.resolution_hz, 400.0 / w["segment"].get<double>());
  ASSERT_TRUE(s.series.has_value());
  expect_same_psd(s, "recommend_one_mode_psd.csv", "psd_x");
  expect_same_psd(load("recommend_decay.csv", "2"), "recommend_decay_psd.csv", "psd_xyz");
}

TEST(SpectrumInput, KlipperRawAxesAndTheirSumMatchScipy) {
  const ad::MeasuredSpectrum x = load("recommend_klipper_raw.csv", "accel_x");
  EXPECT_EQ(x.format, ad::InputFormat::klipper_raw);
  EXPECT_EQ(x.column, "accel_x");
  expect_same_psd(x, "recommend_klipper_raw_psd.csv", "psd_x");
  expect_same_psd(load("recommend_klipper_raw.csv", "y"), "recommend_klipper_raw_psd.csv", "psd_y");
  const ad::MeasuredSpectrum sum = load("recommend_klipper_raw.csv", "");  // default: xyz
  EXPECT_EQ(sum.column, "xyz");
  EXPECT_FALSE(sum.series.has_value());
  expect_same_psd(sum, "recommend_klipper_raw_psd.csv", "psd_xyz");
}

TEST(SpectrumInput, KlipperPsdIgnoresItsShaperColumns) {
  const auto p = write_temp("psd_shapers.csv",
                            "freq,psd_x,psd_y,psd_z,psd_xyz,shapers:,zv(40.0)\n0.0,1e-3,2e-3,3e-3,6e-3,,0.5\n"
                            "1.6,1e-2,2e-2,3e-2,6e-2,,0.6\n3.1,1e-3,2e-3,3e-3,6e-3,,0.7\n");
  ad::SpectrumRequest r;
  r.path = p;
  const ad::MeasuredSpectrum s = ad::load_spectrum(r);
  std::filesystem::remove(p);
  EXPECT_EQ(s.column, "psd_xyz");
  ASSERT_EQ(s.power.size(), 3u);
  EXPECT_DOUBLE_EQ(s.power[1], 6e-2);
  EXPECT_DOUBLE_EQ(s.frequency_hz[2], 3.1);
}

TEST(SpectrumInput, ErrorsNameFileLineAndField) {
  std::string e = error_of("raw_bad.csv", "#time,accel_x,accel_y,accel_z\n0.0,1,2,3\n0.001,1,abc,3\n", "x");
  EXPECT_NE(e.find("raw_bad.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("3"), std::string::npos) << e;
  EXPECT_NE(e.find("accel_y"), std::string::npos) << e;
  e = error_of("raw_short.csv", "#time,accel_x,accel_y,accel_z\n0.0,1,2,3\n0.001,1,2\n", "x");
  EXPECT_NE(e.find("accel_z"), std::string::npos) << e;
  e = error_of("raw_time.csv", "#time,accel_x,accel_y,accel_z\n0.0,1,2,3\n0.0,1,2,3\n", "x");
  EXPECT_NE(e.find("time"), std::string::npos) << e;
  EXPECT_NE(e.find("does not increase"), std::string::npos) << e;
  e = error_of("psd_neg.csv", "freq,psd_x,psd_y,psd_z,psd_xyz\n0,1,1,1,3\n1,1,-1,1,3\n2,1,1,1,3\n", "xyz");
  EXPECT_NE(e.find("psd_y"), std::string::npos) << e;
  EXPECT_NE(e.find("negative"), std::string::npos) << e;
  e = error_of("psd_header.csv", "freq,psd_x,psd_q,psd_z,psd_xyz\n0,1,1,1,3\n", "xyz");
  EXPECT_NE(e.find("psd_y"), std::string::npos) << e;
}

TEST(SpectrumInput, RejectsAColumnTheFormatDoesNotHave) {
  EXPECT_THROW((void)load("recommend_klipper_raw.csv", "psd_x"), clearshape::InvalidArgument);
  EXPECT_THROW((void)load("recommend_one_mode.csv", ""), clearshape::InvalidArgument);
  EXPECT_THROW((void)load("recommend_one_mode.csv", "nope"), clearshape::InputError);
}

TEST(SpectrumInput, WindowCutsTheRecord) {
  ad::SpectrumRequest r;
  r.path = clearshape::testing::golden_path("recommend_decay.csv");
  r.column = "gyro_deg_s";
  r.from_s = 0.5;
  r.to_s = 2.5;
  const ad::MeasuredSpectrum s = ad::load_spectrum(r);
  ASSERT_TRUE(s.series.has_value());
  EXPECT_EQ(s.series->size(), 1000u);
  EXPECT_NEAR(s.series->start_s, 0.5, 1e-12);
  r.from_s = 5.0;
  EXPECT_THROW((void)ad::load_spectrum(r), clearshape::InvalidArgument);
}
