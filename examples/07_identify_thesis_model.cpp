// Thesis §4.2 end to end: record a step and a PRBS run of the speed-mode drive (Eq. 4.2, simulated
// here with 1 % sensor noise), identify the P3UZ process model from both runs at once, read
// ωn = 1/Tw and ζ = Zeta with their uncertainty, and design the ZVD shaper from them.
// Exits non-zero if the truth lies outside 4σ or the shaper leaves > 5 % vibration at the truth.
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "clearshape/ident/process_fit.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/shaping/design.hpp"
#include "clearshape/shaping/residual.hpp"

namespace ident = clearshape::ident;
namespace lti = clearshape::lti;
namespace sh = clearshape::shaping;

int main() {
  const lti::ProcessModel truth = lti::thesis_speed_mode_model();
  const double dt = 1e-3;  // 1 kHz logging
  std::mt19937_64 rng(2015);
  std::normal_distribution<double> noise(0.0, 1.0);
  std::vector<double> step(3001, 1.0), prbs(3001);
  double level = 1.0;
  for (std::size_t k = 0; k < prbs.size(); ++k) prbs[k] = (k % 20 == 0 && (rng() & 1U)) ? (level = -level) : level;
  std::vector<ident::Experiment> runs;
  for (const auto* u : {&step, &prbs}) {
    auto y = lti::simulate(truth, clearshape::UniformSeries{0.0, dt, *u}).values;
    for (double& v : y) v += 0.01 * 25.47 * noise(rng);  // 1 % of the step's final value
    runs.push_back({u == &step ? "step" : "prbs", dt, *u, y});
  }
  const ident::ProcessEstimate est = ident::estimate_process_model(truth.structure(), runs);
  int failures = 0;
  std::printf("P3UZ from step + PRBS (%zu samples), fit %.2f %%\n", est.samples, est.fit_percent());
  for (const auto& p : est.parameters) {
    const double t = truth.parameters().get(p.name);
    const bool ok = std::abs(p.value - t) < 4.0 * p.std_dev;
    failures += ok ? 0 : 1;
    std::printf("  %-5s %11.6g ± %-10.3g (thesis %g)%s\n", p.name.c_str(), p.value, p.std_dev, t, ok ? "" : "  <- outside 4σ");
  }
  const sh::Mode mode{*est.natural_frequency_rad_s(), *est.damping_ratio()};  // ωn = 1/Tw, ζ = Zeta (§4.2)
  std::printf("  wn = %.4f ± %.4f rad/s, zeta = %.4f ± %.4f\n", mode.natural_frequency_rad_s,
              *est.natural_frequency_std_rad_s(), mode.damping_ratio, *est.damping_ratio_std());
  const sh::Shaper zvd = sh::design_zvd(mode);
  const double v = sh::residual_vibration(zvd, {1.0 / 0.0479, 0.288});
  std::printf("ZVD from the estimate: %zu impulses over %.4f s; residual vibration at the thesis mode %.2e\n", zvd.size(),
              zvd.duration_s(), v);
  failures += v < 0.05 ? 0 : 1;
  return failures == 0 ? 0 : 1;
}
