// Cross spectrum, H1 and coherence against scipy.signal.csd / welch / coherence
// (tests/golden/gen_frf.py; tolerance 1e-9 relative to each case's largest value), and against
// the analytic transfer function of a 2nd-order resonance (Bendat & Piersol, Random Data, 4th ed., ch. 9).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <cstdio>
#include <random>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/frf.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "golden_json.hpp"

namespace cs = clearshape;
namespace dsp = clearshape::dsp;
using dsp::testing::load_golden;
using dsp::testing::max_abs;
using dsp::testing::max_abs_diff;
using dsp::testing::options_of;
using dsp::testing::to_complex;
using dsp::testing::to_vector;

namespace {

double max_rel_complex(const std::vector<std::complex<double>>& ours, const std::vector<std::complex<double>>& ref) {
  EXPECT_EQ(ours.size(), ref.size());
  double scale = 0.0, worst = 0.0;
  for (const auto& v : ref) scale = std::max(scale, std::abs(v));
  for (std::size_t k = 0; k < std::min(ours.size(), ref.size()); ++k) worst = std::max(worst, std::abs(ours[k] - ref[k]));
  return worst / scale;
}

// Continuous K·ωn²/(s² + 2ζωn s + ωn²) by the bilinear transform prewarped at ωn, so the digital
// response at fn equals the analytic one exactly: K/(2ζ) at −90° (Oppenheim & Schafer §7.1.2).
dsp::SosDesign resonance(double fn_hz, double zeta, double gain, double fs) {
  const double wn = cs::kTwoPi * fn_hz;
  const double c = wn / std::tan(wn / (2.0 * fs));  // prewarped s = c (z − 1)/(z + 1)
  const double num = gain * wn * wn;
  const double a0 = c * c + 2.0 * zeta * wn * c + wn * wn;
  const double a1 = 2.0 * (wn * wn - c * c);
  const double a2 = c * c - 2.0 * zeta * wn * c + wn * wn;
  return dsp::SosDesign({dsp::Section{num, 2.0 * num, num, a0, a1, a2}}, fs);
}

}  // namespace

TEST(Frf, MatchesScipyCsdWelchCoherence) {
  const auto golden = load_golden("dsp_frf.json");
  const double fs = golden["fs_hz"].get<double>();
  const auto x = to_vector(golden["x"]);
  const auto y = to_vector(golden["y"]);
  double worst = 0.0;
  for (const auto& c : golden["cases"]) {
    const auto o = options_of(c);
    const auto pxy = dsp::csd(x, y, fs, o);
    const auto h = dsp::estimate_frequency_response(x, y, fs, o);
    EXPECT_LT(max_abs_diff(pxy.frequency_hz, to_vector(c["frequency_hz"])), 1e-12);
    EXPECT_LT(max_abs_diff(h.frequency_hz, to_vector(c["frequency_hz"])), 1e-12);
    const double e_pxy = max_rel_complex(pxy.power, to_complex(c["pxy"]));
    const double e_h1 = max_rel_complex(h.response, to_complex(c["h1"]));
    const double e_pxx = max_abs_diff(h.input_psd, to_vector(c["pxx"])) / max_abs(to_vector(c["pxx"]));
    const double e_pyy = max_abs_diff(h.output_psd, to_vector(c["pyy"])) / max_abs(to_vector(c["pyy"]));
    const double e_coh = max_abs_diff(h.coherence, to_vector(c["coherence"]));  // coherence ≤ 1: absolute
    for (double e : {e_pxy, e_h1, e_pxx, e_pyy, e_coh}) {
      EXPECT_LT(e, 1e-9) << c["window"] << " nperseg " << c["nperseg"];
      worst = std::max(worst, e);
    }
  }
  std::printf("[ dsp ] frf: max relative |ours - scipy| over csd, welch, H1, coherence = %.3g\n", worst);
}

TEST(Frf, ResonanceMatchesTheAnalyticTransferFunction) {
  const double fs = 1000.0, fn = 40.0, zeta = 0.05, gain = 2.0;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> white(0.0, 1.0);
  std::vector<double> u(1 << 17);
  for (double& v : u) v = white(rng);
  const auto y = dsp::sosfilt(resonance(fn, zeta, gain, fs), u);
  dsp::WelchOptions o;
  o.segment_length = 4000;  // 0.25 Hz bins: 16 inside the 4 Hz half-power band; fn = bin 160
  const auto h = dsp::estimate_frequency_response(u, y, fs, o);
  const std::size_t k = 160;
  ASSERT_DOUBLE_EQ(h.frequency_hz[k], fn);
  // Analytic: |G(j2πfn)| = K/(2ζ) = 20, ∠ = −90°. Tolerance 1 % and 1°: the resolution bias at a
  // peak, −(1/3)(Be/Br)² ≈ −0.3 % (Hann bandwidth Be = 1.5 bins, half-power width Br = 2ζfn), plus
  // the random error √(1−γ²)/(|γ|√(2nd)) ≈ 0.7 % (Bendat & Piersol, Random Data, 4th ed., ch. 8–9).
  EXPECT_NEAR(h.magnitude()[k], gain / (2.0 * zeta), 0.01 * gain / (2.0 * zeta));
  EXPECT_NEAR(h.phase_deg()[k], -90.0, 1.0);
  // Off resonance (100 Hz): the analytic K·ωn²/(ωn² − ωa² + 2jζωn·ωa) at the frequency the prewarped
  // bilinear map sends 100 Hz to, ωa = c·tan(π·100/fs), c = ωn / tan(ωn/(2fs)).
  const std::size_t k100 = 400;
  const double wn = cs::kTwoPi * fn;
  const double wa = wn / std::tan(wn / (2.0 * fs)) * std::tan(cs::kPi * 100.0 / fs);
  const std::complex<double> g = gain * wn * wn / std::complex<double>(wn * wn - wa * wa, 2.0 * zeta * wn * wa);
  EXPECT_NEAR(h.magnitude()[k100], std::abs(g), 0.01 * std::abs(g));
  EXPECT_NEAR(h.phase_deg()[k100], std::arg(g) * 180.0 / cs::kPi, 1.0);
  // Noise-free: coherence ≈ 1 wherever the system passes the input (here up to 300 Hz).
  double min_coherence = 1.0;
  for (std::size_t i = 1; i < 1200; ++i) min_coherence = std::min(min_coherence, h.coherence[i]);
  EXPECT_GT(min_coherence, 0.99);
  std::printf("[ dsp ] frf resonance: |H1(fn)| = %.4f (analytic 20), phase %.3f deg (analytic -90), min coherence %.5f\n",
              h.magnitude()[k], h.phase_deg()[k], min_coherence);
}

TEST(Frf, OutputNoiseLowersCoherenceAsPredicted) {
  // y = u + n, n independent white of variance σ²: Cxy = 1/(1 + σ²) at every frequency (Bendat & Piersol, ch. 9: γ² = Gvv/Gyy).
  std::mt19937_64 rng(11);
  std::normal_distribution<double> white(0.0, 1.0);
  const std::size_t n = 1 << 17;
  std::vector<double> u(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    u[i] = white(rng);
    y[i] = u[i] + 0.5 * white(rng);
  }
  const auto h = dsp::estimate_frequency_response(u, y, 100.0);
  double mean = 0.0, gain = 0.0;
  for (std::size_t k = 1; k + 1 < h.coherence.size(); ++k) {
    mean += h.coherence[k];
    gain += h.magnitude()[k];
  }
  mean /= static_cast<double>(h.coherence.size() - 2);
  gain /= static_cast<double>(h.coherence.size() - 2);
  EXPECT_NEAR(mean, 1.0 / 1.25, 0.01);
  EXPECT_NEAR(gain, 1.0, 0.01);  // H1 is unbiased by output noise
}

TEST(Frf, RejectsBadInput) {
  std::vector<double> x(1000, 0.0), y(1000, 1.0);
  EXPECT_THROW(dsp::estimate_frequency_response(x, y, 100.0), cs::InvalidArgument);  // constant input
  x[3] = 1.0;
  EXPECT_NO_THROW(dsp::estimate_frequency_response(x, y, 100.0));
  std::vector<double> shorter(999, 0.0);
  EXPECT_THROW(dsp::csd(x, shorter, 100.0), cs::InvalidArgument);
  dsp::WelchOptions o;
  o.segment_length = 2000;
  try {
    dsp::estimate_frequency_response(x, y, 100.0, o);
    ADD_FAILURE() << "a segment longer than the record was accepted";
  } catch (const cs::InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("segment_length = 2000"), std::string::npos) << e.what();
  }
  y[10] = std::nan("");
  EXPECT_THROW(dsp::estimate_frequency_response(x, y, 100.0), cs::InvalidArgument);
  EXPECT_EQ(dsp::matlab_default_segment_length(9000), 2000u);
}
