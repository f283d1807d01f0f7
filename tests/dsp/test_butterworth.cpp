// Butterworth design and zpk → SOS conversion against scipy.signal (tests/golden/gen_dsp.py).
// Tolerances: coefficients 1e-12 relative to each section's largest coefficient; poles, zeros
// and frequency response 1e-12; gain 1e-12 relative.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/butterworth.hpp"
#include "clearshape/dsp/encoder_speed.hpp"
#include "golden_json.hpp"

namespace cs = clearshape;
namespace dsp = clearshape::dsp;
using dsp::testing::load_golden;

namespace {

dsp::ButterworthSpec spec_of(const nlohmann::json& c) {
  dsp::ButterworthSpec spec;
  spec.order = c["order"].get<int>();
  const std::string btype = c["btype"].get<std::string>();
  spec.type = btype == "lowpass" ? dsp::BandType::lowpass
              : btype == "highpass" ? dsp::BandType::highpass
                                    : dsp::BandType::bandpass;
  spec.cutoff_hz = c["cutoff_hz"][0].get<double>();
  if (spec.type == dsp::BandType::bandpass) spec.cutoff_high_hz = c["cutoff_hz"][1].get<double>();
  spec.sample_rate_hz = c["fs_hz"].get<double>();
  return spec;
}

}  // namespace

TEST(Butterworth, SosMatchesScipy) {
  const auto golden = load_golden("dsp_butter.json");
  double worst = 0.0;
  for (const auto& c : golden["butter"]) {
    const dsp::ButterworthSpec spec = spec_of(c);
    const dsp::SosDesign design = dsp::butter(spec);
    const double diff = dsp::testing::max_sos_diff(design.sections(), dsp::testing::to_sections(c["sos"]));
    EXPECT_LT(diff, 1e-12) << c["btype"] << " order " << spec.order << " at " << spec.cutoff_hz << " Hz";
    worst = std::max(worst, diff);
  }
  std::printf("[ dsp ] butter sos: max relative coefficient difference vs scipy = %.3g\n", worst);
}

TEST(Butterworth, EveryOrderAndBandTypeMatchesScipy) {
  // Seeded sweep: orders 1..16 × {lowpass, highpass, bandpass}, log-uniform cutoffs.
  const auto golden = load_golden("dsp_butter.json");
  ASSERT_EQ(golden["sweep"].size(), 48u);
  double worst = 0.0;
  for (const auto& c : golden["sweep"]) {
    const dsp::SosDesign design = dsp::butter(spec_of(c));
    const double diff = dsp::testing::max_sos_diff(design.sections(), dsp::testing::to_sections(c["sos"]));
    EXPECT_LT(diff, 1e-12) << c.dump();
    worst = std::max(worst, diff);
  }
  std::printf("[ dsp ] butter sweep (48 designs): max relative coefficient difference = %.3g\n", worst);
}

TEST(Butterworth, ZpkMatchesScipy) {
  const auto golden = load_golden("dsp_butter.json");
  for (const auto& c : golden["butter"]) {
    const dsp::Zpk zpk = dsp::butter_zpk(spec_of(c));
    const auto zeros = dsp::testing::to_complex(c["zeros"]);
    const auto poles = dsp::testing::to_complex(c["poles"]);
    ASSERT_EQ(zpk.zeros.size(), zeros.size());
    ASSERT_EQ(zpk.poles.size(), poles.size());
    for (std::size_t i = 0; i < zeros.size(); ++i) EXPECT_LT(std::abs(zpk.zeros[i] - zeros[i]), 1e-12);
    for (std::size_t i = 0; i < poles.size(); ++i) EXPECT_LT(std::abs(zpk.poles[i] - poles[i]), 1e-12);
    const double k = c["gain"].get<double>();
    EXPECT_NEAR(zpk.gain, k, 1e-12 * std::abs(k));
  }
}

TEST(Butterworth, FrequencyResponseMatchesScipySosfreqz) {
  const auto golden = load_golden("dsp_butter.json");
  for (const auto& c : golden["butter"]) {
    const dsp::SosDesign design = dsp::butter(spec_of(c));
    const auto f = dsp::testing::to_vector(c["response_f_hz"]);
    const auto h = dsp::testing::to_complex(c["response"]);
    for (std::size_t i = 0; i < f.size(); ++i) {
      EXPECT_LT(std::abs(design.response(f[i]) - h[i]), 1e-12) << "f = " << f[i] << " Hz";
    }
  }
}

TEST(Butterworth, MinusThreeDecibelsExactlyAtTheCutoff) {
  // Pre-warped bilinear design: |H(f_c)| = 1/√2 for every order (closed form of a Butterworth).
  for (int order = 1; order <= dsp::kMaxButterworthOrder; ++order) {
    for (double fc : {0.3, 4.7746482927568605, 120.0, 470.0}) {
      const auto lp = dsp::butter_lowpass(order, fc, 1000.0);
      const auto hp = dsp::butter_highpass(order, fc, 1000.0);
      EXPECT_NEAR(lp.magnitude(fc), std::sqrt(0.5), 1e-9) << "order " << order << " fc " << fc;
      EXPECT_NEAR(hp.magnitude(fc), std::sqrt(0.5), 1e-9) << "order " << order << " fc " << fc;
      EXPECT_NEAR(lp.dc_gain(), 1.0, 1e-9);
      EXPECT_NEAR(hp.magnitude(500.0), 1.0, 1e-9);  // Nyquist
      EXPECT_NEAR(hp.dc_gain(), 0.0, 1e-9);
    }
  }
  const auto bp = dsp::butter_bandpass(3, 20.0, 80.0, 1000.0);
  EXPECT_NEAR(bp.magnitude(20.0), std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(bp.magnitude(80.0), std::sqrt(0.5), 1e-12);
  // Peak at the pre-warped geometric centre: tan(πf0/fs)² = tan(πf1/fs)·tan(πf2/fs).
  const double f0 = 1000.0 / cs::kPi *
                    std::atan(std::sqrt(std::tan(cs::kPi * 0.02) * std::tan(cs::kPi * 0.08)));
  EXPECT_NEAR(bp.magnitude(f0), 1.0, 1e-12);
}

TEST(Butterworth, ThesisPresetIsTheFourthOrder30RadPerSecondFilter) {
  const auto golden = load_golden("dsp_butter.json");
  const auto& thesis = golden["butter"][0];
  ASSERT_EQ(thesis["order"].get<int>(), 4);
  EXPECT_DOUBLE_EQ(thesis["cutoff_hz"][0].get<double>(), 30.0 / (2.0 * cs::kPi));
  const dsp::SosDesign design = dsp::thesis_speed_filter(1e-3);
  EXPECT_EQ(design.section_count(), 2u);
  EXPECT_DOUBLE_EQ(design.sample_rate_hz(), 1000.0);
  EXPECT_LT(dsp::testing::max_sos_diff(design.sections(), dsp::testing::to_sections(thesis["sos"])), 1e-12);
  EXPECT_NEAR(design.magnitude(cs::rad_s_to_hz(30.0)), std::sqrt(0.5), 1e-12);
  // rad/s helper and Hz entry point agree.
  const auto by_rad = dsp::butter_lowpass_rad_s(4, 30.0, 1000.0);
  EXPECT_EQ(dsp::testing::max_sos_diff(by_rad.sections(), design.sections()), 0.0);
}

TEST(Butterworth, RejectsOutOfRangeSpecifications) {
  EXPECT_THROW(dsp::butter_lowpass(0, 10.0, 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_lowpass(17, 10.0, 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_lowpass(4, 0.0, 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_lowpass(4, -1.0, 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_lowpass(4, 500.0, 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_highpass(4, 600.0, 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_lowpass(4, 10.0, 0.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_lowpass(4, std::nan(""), 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_bandpass(2, 50.0, 40.0, 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::butter_bandpass(2, 50.0, 500.0, 1000.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::thesis_speed_filter(0.2), cs::InvalidArgument);  // 30 rad/s above Nyquist
  try {
    dsp::butter_lowpass(4, 600.0, 1000.0);
    FAIL();
  } catch (const cs::InvalidArgument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("cutoff_hz = 600"), std::string::npos) << message;
    EXPECT_NE(message.find("Nyquist"), std::string::npos) << message;
  }
}

TEST(ZpkToSos, MatchesScipyOnGeneralSystems) {
  const auto golden = load_golden("dsp_butter.json");
  for (const auto& c : golden["zpk2sos"]) {
    dsp::Zpk zpk{dsp::testing::to_complex(c["zeros"]), dsp::testing::to_complex(c["poles"]),
                 c["gain"].get<double>()};
    const auto sos = dsp::zpk_to_sos(zpk);
    EXPECT_LT(dsp::testing::max_sos_diff(sos, dsp::testing::to_sections(c["sos"])), 1e-12)
        << c["sos"].dump();
  }
}

TEST(ZpkToSos, EmptySystemIsAGainAndUnpairedRootsAreRejected) {
  const auto sos = dsp::zpk_to_sos(dsp::Zpk{{}, {}, 2.5});
  ASSERT_EQ(sos.size(), 1u);
  EXPECT_EQ(sos[0].b0, 2.5);
  EXPECT_EQ(sos[0].a0, 1.0);
  EXPECT_THROW(dsp::zpk_to_sos(dsp::Zpk{{}, {{0.5, 0.5}}, 1.0}), cs::InvalidArgument);
}

TEST(SosDesign, ValidatesAndNormalizes) {
  const dsp::SosDesign d({dsp::Section{2.0, 4.0, 2.0, 2.0, 1.0, 0.5}}, 100.0);
  EXPECT_EQ(d.sections()[0].a0, 1.0);
  EXPECT_EQ(d.sections()[0].b1, 2.0);
  EXPECT_EQ(d.sections()[0].a2, 0.25);
  EXPECT_THROW(dsp::SosDesign({}, 100.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::SosDesign({dsp::Section{1, 0, 0, 0, 1, 0}}, 100.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::SosDesign({dsp::Section{1, 0, 0, 1, 0, 0}}, -1.0), cs::InvalidArgument);
  EXPECT_THROW(dsp::SosDesign({dsp::Section{1, std::nan(""), 0, 1, 0, 0}}, 1.0), cs::InvalidArgument);
}
