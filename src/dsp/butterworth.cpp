#include "clearshape/dsp/butterworth.hpp"

#include <cmath>
#include <complex>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"

namespace clearshape::dsp {

using Complex = std::complex<double>;

namespace {

void validate(const ButterworthSpec& spec) {
  if (spec.order < 1 || spec.order > kMaxButterworthOrder) {
    throw_invalid("order", spec.order, fmt::format("an integer in [1, {}]", kMaxButterworthOrder),
                  "Use cascaded designs for steeper roll-off");
  }
  require_positive("sample_rate_hz", spec.sample_rate_hz);
  const double nyquist_hz = spec.sample_rate_hz / 2.0;
  const std::string remedy = fmt::format(
      "A digital cutoff must lie strictly between 0 and the Nyquist frequency fs/2 = {} Hz; "
      "lower it or raise the sample rate", nyquist_hz);
  require_in_open("cutoff_hz", spec.cutoff_hz, 0.0, nyquist_hz, remedy);
  if (spec.type == BandType::bandpass) {
    require_in_open("cutoff_high_hz", spec.cutoff_high_hz, spec.cutoff_hz, nyquist_hz,
                    "The band-pass upper edge must exceed the lower edge cutoff_hz and stay below "
                    "Nyquist");
  }
}

// Analog Butterworth prototype, cutoff 1 rad/s (scipy buttap): p_m = −exp(jπm/2N),
// m = −N+1, −N+3, …, N−1 (m = 0 gives the exactly real pole of odd orders).
std::vector<Complex> prototype_poles(int order) {
  std::vector<Complex> p;
  p.reserve(static_cast<std::size_t>(order));
  for (int m = -order + 1; m < order; m += 2) {
    const double theta = kPi * m / (2.0 * order);
    p.push_back(-Complex(std::cos(theta), std::sin(theta)));
  }
  return p;
}

Complex product(const std::vector<Complex>& v, double shift) {
  Complex acc{1.0, 0.0};
  for (const Complex& c : v) acc *= (shift - c);
  return acc;
}

}  // namespace

Zpk butter_zpk(const ButterworthSpec& spec) {
  validate(spec);
  const int n = spec.order;
  // Digital design normalized to fs = 2 (half-cycles per sample), as scipy.signal.iirfilter.
  constexpr double fs = 2.0;
  auto prewarp = [&](double cutoff_hz) {
    const double wn = 2.0 * cutoff_hz / spec.sample_rate_hz;
    return 2.0 * fs * std::tan(kPi * wn / fs);  // bilinear pre-warping: Ω = 2·fs·tan(ω/2)
  };
  const std::vector<Complex> proto = prototype_poles(n);
  std::vector<Complex> zeros;  // analog zeros
  std::vector<Complex> poles;
  double gain = 1.0;
  switch (spec.type) {
    case BandType::lowpass: {  // s → s / Ωc
      const double wo = prewarp(spec.cutoff_hz);
      for (const Complex& p : proto) poles.push_back(p * wo);
      gain = std::pow(wo, n);
      break;
    }
    case BandType::highpass: {  // s → Ωc / s
      const double wo = prewarp(spec.cutoff_hz);
      for (const Complex& p : proto) poles.push_back(wo / p);
      zeros.assign(static_cast<std::size_t>(n), Complex{0.0, 0.0});
      gain = (1.0 / product(proto, 0.0)).real();  // k · Π(−z) / Π(−p), no prototype zeros
      break;
    }
    case BandType::bandpass: {  // s → (s² + Ωo²) / (s · BW)
      const double w_low = prewarp(spec.cutoff_hz);
      const double w_high = prewarp(spec.cutoff_high_hz);
      const double bw = w_high - w_low;
      const double wo = std::sqrt(w_low * w_high);
      std::vector<Complex> upper, lower;
      for (const Complex& p : proto) {
        const Complex p_lp = p * bw / 2.0;
        const Complex root = std::sqrt(p_lp * p_lp - wo * wo);
        upper.push_back(p_lp + root);
        lower.push_back(p_lp - root);
      }
      poles = upper;
      poles.insert(poles.end(), lower.begin(), lower.end());
      zeros.assign(static_cast<std::size_t>(n), Complex{0.0, 0.0});
      gain = std::pow(bw, n);
      break;
    }
  }
  // Bilinear transform s = 2·fs·(z − 1)/(z + 1) (scipy bilinear_zpk); zeros at infinity go to
  // z = −1 and the gain compensates Π(2fs − z)/Π(2fs − p).
  const double fs2 = 2.0 * fs;
  Zpk out;
  for (const Complex& z : zeros) out.zeros.push_back((fs2 + z) / (fs2 - z));
  for (const Complex& p : poles) out.poles.push_back((fs2 + p) / (fs2 - p));
  out.zeros.resize(out.poles.size(), Complex{-1.0, 0.0});
  out.gain = gain * (product(zeros, fs2) / product(poles, fs2)).real();
  return out;
}

SosDesign butter(const ButterworthSpec& spec) {
  return SosDesign(zpk_to_sos(butter_zpk(spec)), spec.sample_rate_hz);
}

SosDesign butter_lowpass(int order, double cutoff_hz, double sample_rate_hz) {
  return butter({order, BandType::lowpass, cutoff_hz, 0.0, sample_rate_hz});
}

SosDesign butter_highpass(int order, double cutoff_hz, double sample_rate_hz) {
  return butter({order, BandType::highpass, cutoff_hz, 0.0, sample_rate_hz});
}

SosDesign butter_bandpass(int order, double low_hz, double high_hz, double sample_rate_hz) {
  return butter({order, BandType::bandpass, low_hz, high_hz, sample_rate_hz});
}

SosDesign butter_lowpass_rad_s(int order, double cutoff_rad_s, double sample_rate_hz) {
  return butter_lowpass(order, rad_s_to_hz(cutoff_rad_s), sample_rate_hz);
}

SosDesign butter_highpass_rad_s(int order, double cutoff_rad_s, double sample_rate_hz) {
  return butter_highpass(order, rad_s_to_hz(cutoff_rad_s), sample_rate_hz);
}

}  // namespace clearshape::dsp
