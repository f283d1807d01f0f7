// Welch PSD against scipy.signal.welch and peak picking against scipy.signal.find_peaks /
// peak_prominences (tests/golden/gen_dsp.py). Tolerance: 1e-10 relative to the largest PSD
// value of each case; frequencies 1e-12 Hz; peak indices exact, prominences 1e-10 relative.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/peaks.hpp"
#include "clearshape/dsp/welch.hpp"
#include "golden_json.hpp"

namespace cs = clearshape;
namespace dsp = clearshape::dsp;
using dsp::testing::load_golden;
using dsp::testing::max_abs;
using dsp::testing::max_abs_diff;
using dsp::testing::options_of;
using dsp::testing::to_vector;

TEST(Welch, MatchesScipy) {
  const auto golden = load_golden("dsp_welch.json");
  const double fs = golden["fs_hz"].get<double>();
  const auto x = to_vector(golden["x"]);
  double worst = 0.0;
  for (const auto& c : golden["cases"]) {
    const dsp::Spectrum s = dsp::welch(x, fs, options_of(c));
    const auto f_ref = to_vector(c["frequency_hz"]);
    const auto p_ref = to_vector(c["psd"]);
    EXPECT_LT(max_abs_diff(s.frequency_hz, f_ref), 1e-12);
    const double rel = max_abs_diff(s.power, p_ref) / max_abs(p_ref);
    EXPECT_LT(rel, 1e-10) << c["window"] << " nperseg " << c["nperseg"];
    worst = std::max(worst, rel);
  }
  std::printf("[ dsp ] welch: max |ours - scipy| / max(psd) = %.3g\n", worst);
}

TEST(Welch, SinusoidPowerAndWhiteNoiseDensity) {
  // Spectrum scaling: a sinusoid of amplitude A centred on a bin reads A²/2 (its mean power).
  const double fs = 1000.0;
  const std::size_t n = 8192;
  std::vector<double> x(n);
  const double f0 = 125.0;  // bin 32 of a 256-point FFT
  for (std::size_t i = 0; i < n; ++i) x[i] = 3.0 * std::sin(cs::kTwoPi * f0 * static_cast<double>(i) / fs);
  dsp::WelchOptions o;
  o.scaling = dsp::SpectralScaling::spectrum;
  const auto s = dsp::welch(x, fs, o);
  EXPECT_NEAR(s.power[32], 4.5, 1e-9);
  EXPECT_EQ(s.segments, (n - 128) / 128);
  // Density scaling: white noise of variance σ² has a flat one-sided density 2σ²/fs (Parseval).
  std::mt19937_64 rng(20150601);
  std::normal_distribution<double> noise(0.0, 0.7);
  std::vector<double> w(1 << 18);
  for (double& v : w) v = noise(rng);
  const auto d = dsp::welch(w, fs);
  double mean = 0.0;
  for (std::size_t k = 1; k + 1 < d.power.size(); ++k) mean += d.power[k];
  mean /= static_cast<double>(d.power.size() - 2);
  EXPECT_NEAR(mean, 2.0 * 0.49 / fs, 0.02 * 2.0 * 0.49 / fs);
}

TEST(Welch, RejectsBadOptions) {
  std::vector<double> x(100, 1.0);
  dsp::WelchOptions o;
  EXPECT_THROW(dsp::welch(x, 1000.0, o), cs::InvalidArgument);  // shorter than 256
  o.segment_length = 64;
  EXPECT_NO_THROW(dsp::welch(x, 1000.0, o));
  o.overlap = 64;
  EXPECT_THROW(dsp::welch(x, 1000.0, o), cs::InvalidArgument);
  o.overlap.reset();
  o.fft_length = 32;
  EXPECT_THROW(dsp::welch(x, 1000.0, o), cs::InvalidArgument);
  o.fft_length.reset();
  EXPECT_THROW(dsp::welch(x, 0.0, o), cs::InvalidArgument);
  x[5] = std::nan("");
  EXPECT_THROW(dsp::welch(x, 1000.0, o), cs::InvalidArgument);
}

TEST(Peaks, MatchScipyFindPeaks) {
  const auto golden = load_golden("dsp_welch.json");
  const auto p = to_vector(golden["peak_psd"]);
  for (const auto& c : golden["peaks"]) {
    dsp::PeakOptions o;
    const auto& opt = c["options"];
    if (opt.contains("height")) o.min_height = opt["height"].get<double>();
    if (opt.contains("prominence")) o.min_prominence = opt["prominence"].get<double>();
    if (opt.contains("distance")) o.min_distance = opt["distance"].get<std::size_t>();
    const auto peaks = dsp::find_peaks(p, o);
    const auto idx = c["indices"].get<std::vector<std::size_t>>();
    const auto prom = to_vector(c["prominences"]);
    ASSERT_EQ(peaks.size(), idx.size()) << opt.dump();
    for (std::size_t i = 0; i < idx.size(); ++i) {
      EXPECT_EQ(peaks[i].index, idx[i]);
      EXPECT_NEAR(peaks[i].prominence, prom[i], 1e-10 * max_abs(p));
      EXPECT_EQ(peaks[i].height, p[idx[i]]);
    }
  }
  const auto plateau = to_vector(golden["plateau"]);
  const auto peaks = dsp::find_peaks(plateau);
  const auto idx = golden["plateau_peaks"].get<std::vector<std::size_t>>();
  const auto prom = to_vector(golden["plateau_prominences"]);
  ASSERT_EQ(peaks.size(), idx.size());
  for (std::size_t i = 0; i < idx.size(); ++i) {
    EXPECT_EQ(peaks[i].index, idx[i]);
    EXPECT_EQ(peaks[i].prominence, prom[i]);
  }
}

TEST(Peaks, SpectralPeaksFindTheToneFrequencies) {
  const auto golden = load_golden("dsp_welch.json");
  const auto x = to_vector(golden["x"]);
  dsp::WelchOptions o;
  o.segment_length = 1000;
  const auto s = dsp::welch(x, golden["fs_hz"].get<double>(), o);
  dsp::PeakOptions po;
  po.min_prominence = 1e-3;
  const auto peaks = dsp::spectral_peaks(s, po, 3);
  ASSERT_EQ(peaks.size(), 3u);
  // The generator's tones: 12.5 Hz (A = 1), 47 Hz (0.5), 180 Hz (0.25); highest first.
  const double expected[3] = {12.5, 47.0, 180.0};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(peaks[static_cast<std::size_t>(i)].interpolated_frequency_hz, expected[i], 0.5 * s.resolution_hz());
    EXPECT_NEAR(peaks[static_cast<std::size_t>(i)].frequency_hz, expected[i], s.resolution_hz());
  }
  EXPECT_GT(peaks[0].power, peaks[1].power);
  EXPECT_GT(peaks[1].power, peaks[2].power);
}

TEST(Peaks, ParabolicInterpolationRecoversAParabolaVertex) {
  dsp::Spectrum s;
  for (int k = 0; k < 11; ++k) {
    const double f = 2.0 * k;  // 2 Hz bins
    s.frequency_hz.push_back(f);
    s.power.push_back(10.0 - (f - 9.3) * (f - 9.3));
  }
  const auto peaks = dsp::spectral_peaks(s);
  ASSERT_EQ(peaks.size(), 1u);
  EXPECT_EQ(peaks[0].frequency_hz, 10.0);
  EXPECT_NEAR(peaks[0].interpolated_frequency_hz, 9.3, 1e-12);
  EXPECT_THROW(dsp::find_peaks(s.power, dsp::PeakOptions{0.0, 0, 0.0}), cs::InvalidArgument);
}
