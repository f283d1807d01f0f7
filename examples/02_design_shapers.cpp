// Shapers for the thesis's speed-mode drive mode (Eq. 4.2: ωn = 1/Tw = 20.88 rad/s, ζ = 0.288):
// ZV, ZVD, ZVDD (Eq. 2.22–2.26), EI and an SI shaper for ±30 % frequency uncertainty. Prints
// each one's delay and 5 % insensitivity and exits non-zero unless every ZV-family shaper
// cancels the mode (V = 0, Eq. 2.19), EI meets V = Vtol at the design point, and SI keeps
// V <= 5 % over its band.
#include <cmath>
#include <cstdio>

#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"

namespace sh = clearshape::shaping;

int main() {
  const sh::Mode mode{1.0 / 0.0479, 0.2880};
  bool ok = true;
  std::printf("%-6s %8s %10s %12s\n", "shaper", "delay_s", "V(design)", "I(5 %)");
  auto report = [&](const sh::Shaper& s) {
    const double v = sh::residual_vibration(s, mode);
    const double width = sh::insensitivity(s, mode, 0.05).width();
    std::printf("%-6s %8.4f %10.2e %12.4f\n", s.method().c_str(), s.duration_s(), v, width);
    return v;
  };
  for (int n = 0; n <= 2; ++n) ok &= report(sh::design_zv_derivatives(mode, n)) < 1e-12;
  ok &= std::abs(report(sh::design_ei(mode, 0.05)) - 0.05) < 1e-9;

  sh::SiOptions band;
  band.frequency_low_rad_s = 0.7 * mode.natural_frequency_rad_s;
  band.frequency_high_rad_s = 1.3 * mode.natural_frequency_rad_s;
  const sh::Shaper si = sh::design_si(mode, band);
  report(si);
  for (int k = 0; k <= 200; ++k) {
    const double w = band.frequency_low_rad_s + (band.frequency_high_rad_s - band.frequency_low_rad_s) * k / 200.0;
    ok &= sh::residual_vibration(si, sh::Mode{w, mode.damping_ratio}) <= 0.05 * (1 + 1e-6);
  }
  // A ZVDD covers the same ±30 % band, but SI does it sooner.
  const sh::Shaper zvdd = sh::design_zvdd(mode);
  std::printf("SI delay %.4f s vs ZVDD %.4f s\n", si.duration_s(), zvdd.duration_s());
  ok &= si.duration_s() < zvdd.duration_s();
  std::printf(ok ? "ok\n" : "FAILED\n");
  return ok ? 0 : 1;
}
