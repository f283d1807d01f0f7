// The two drive models identified in the thesis (Eq. 4.2, P3UZ): poles, zeros, ωn = 1/Tw,
// ζ = Zeta (§4.2), DC gain and step-response peak. Exits non-zero if a check fails.
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "clearshape/core/units.hpp"
#include "clearshape/lti/lti.hpp"

namespace lti = clearshape::lti;

int main() {
  int failures = 0;
  auto check = [&](bool ok, const char* what) {
    if (!ok) {
      std::printf("  CHECK FAILED: %s\n", what);
      ++failures;
    }
  };
  const struct { const char* name; lti::ProcessModel model; } drives[] = {
      {"speed mode", lti::thesis_speed_mode_model()}, {"position mode", lti::thesis_position_mode_model()}};
  for (const auto& [name, m] : drives) {
    std::printf("%s (%s): Kp=%g Tz=%g Zeta=%g Tw=%g Tp3=%g\n", name, m.code().c_str(), m.parameters().kp,
                m.parameters().tz, m.parameters().zeta, m.parameters().tw, m.parameters().tp3);
    for (const auto& p : m.poles()) std::printf("  pole  %+10.4f %+10.4fj rad/s\n", p.real(), p.imag());
    for (const auto& z : m.zeros()) std::printf("  zero  %+10.4f rad/s%s\n", z.real(), z.real() > 0 ? "  (right half plane)" : "");
    const double wn = m.natural_frequency_rad_s();
    std::printf("  wn = 1/Tw = %.4f rad/s (%.4f Hz), zeta = %.4f, DC gain = %.4f\n", wn, clearshape::rad_s_to_hz(wn),
                m.damping_ratio(), m.dc_gain());
    const auto step = lti::step_response(m, 4.0, 1e-4);
    const auto peak = std::max_element(step.values.begin(), step.values.end());
    const double t_peak = step.time_s(static_cast<std::size_t>(peak - step.values.begin()));
    const double overshoot = 100.0 * (*peak / m.dc_gain() - 1.0);
    std::printf("  step peak %.4f at %.4f s (overshoot %.2f %%), final %.4f\n", *peak, t_peak, overshoot,
                step.values.back());
    // ωn and ζ read from the poles equal the thesis's ωn = 1/Tw and ζ = Zeta.
    const auto modes = m.oscillatory_modes();
    check(modes.size() == 1, "exactly one oscillatory mode");
    check(std::abs(modes[0].natural_frequency_rad_s - wn) < 1e-9 * wn, "pole wn == 1/Tw");
    check(std::abs(modes[0].damping_ratio - m.damping_ratio()) < 1e-12, "pole zeta == Zeta");
    // The poles and zeros of the expanded polynomial agree with the factored ones.
    const auto tf = m.transfer_function();
    check(std::abs(tf.dc_gain() - m.parameters().kp) < 1e-12 * m.parameters().kp, "H(0) == Kp");
    check(std::abs(tf.zeros()[0] - m.zeros()[0]) < 1e-9 * std::abs(m.zeros()[0]), "numeric zero == -1/Tz");
    check(std::abs(step.values.back() / m.dc_gain() - 1.0) < 1e-6, "step settles at Kp");
  }
  const auto& speed = drives[0].model;
  const auto& position = drives[1].model;
  check(speed.zeros()[0].real() > 25.1 && speed.zeros()[0].real() < 25.2, "speed zero at s = +25.13");
  check(lti::step_response(speed, 0.01, 1e-4).values[20] < 0.0, "speed step undershoots (RHP zero)");
  const auto ps = lti::step_response(position, 1.0, 1e-4);
  check(*std::max_element(ps.values.begin(), ps.values.end()) < 1.01 * position.dc_gain(),
        "position mode (zeta 0.9968) barely overshoots");
  std::printf(failures == 0 ? "all checks passed\n" : "%d check(s) failed\n", failures);
  return failures == 0 ? 0 : 1;
}
