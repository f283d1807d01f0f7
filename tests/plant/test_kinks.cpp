// Kinks of the contact laws (the clamp at F = 0, the bound |F_d| = F_el, the hysteresis factor)
// and the integrator stopping at them: a slow unload under the clamped thesis law must separate
// on time at the plant's default tolerance, not only at a tight one.
#include <gtest/gtest.h>

#include <cmath>

#include "clearshape/core/units.hpp"
#include "clearshape/plant/contact_law.hpp"
#include "clearshape/plant/drive.hpp"
#include "clearshape/plant/simulation.hpp"

namespace cp = clearshape::plant;

TEST(ContactKinks, FunctionsChangeSignExactlyAtTheLawsSwitches) {
  double g[2];
  // clamped Kelvin–Voigt: F = max(kδ + cδ̇, 0), kink where kδ + cδ̇ = 0
  const auto clamped = cp::ContactLaw::kelvin_voigt(100.0, 2.0, cp::DampingPolicy::clamped);
  clamped.kink_functions(0.01, -0.5, {}, g);
  EXPECT_DOUBLE_EQ(g[0], 100.0 * 0.01 - 2.0 * 0.5);  // exactly 0 at the switch
  EXPECT_EQ(g[1], 1.0);
  clamped.kink_functions(0.01, -0.6, {}, g);
  EXPECT_LT(g[0], 0.0);
  EXPECT_EQ(clamped.evaluate(0.01, -0.6, {}).force, 0.0);  // clamped side: no force
  EXPECT_GT(clamped.evaluate(0.01, -0.4, {}).force, 0.0);
  // bounded (ElastoBacklash): kinks at F_d = −F_el and F_d = +F_el
  const auto bounded = cp::ContactLaw::hertz_dashpot(8.0, 1.5, 3.0, cp::DampingPolicy::bounded);
  const double fe = 8.0 * std::pow(0.04, 1.5);
  bounded.kink_functions(0.04, fe / 3.0, {}, g);
  EXPECT_NEAR(g[1], 0.0, 1e-15);
  EXPECT_NEAR(g[0], 2.0 * fe, 1e-15);
  bounded.kink_functions(0.04, -fe / 3.0, {}, g);
  EXPECT_NEAR(g[0], 0.0, 1e-15);
  // raw: no kink inside the contact
  cp::ContactLaw::thesis_speed_mode(cp::DampingPolicy::raw).kink_functions(0.01, -5.0, {}, g);
  EXPECT_EQ(g[0], 1.0);
  EXPECT_EQ(g[1], 1.0);
  // hysteresis (Lankarani–Nikravesh): the factor 1 + χ δ̇/δ̇⁻ vanishes where F reaches 0
  const auto ln = cp::ContactLaw::lankarani_nikravesh(1e4, 1.5, 0.5);
  cp::ContactMemory memory{0.2, false};
  ln.kink_functions(0.001, 0.0, memory, g);
  EXPECT_DOUBLE_EQ(g[0], 1.0);
  double lo = -10.0, hi = 0.0;  // bisect F(δ̇) = 0 and compare with the kink function's zero
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (ln.evaluate(0.001, mid, memory).force > 0.0 ? hi : lo) = mid;
  }
  ln.kink_functions(0.001, hi, memory, g);
  EXPECT_NEAR(g[0], 0.0, 1e-12);
}

// The case that found the problem: the thesis speed drive (Eq. 4.2) turns a link pressed on its
// stop (φ(0) = +β, 1° total play) with the thesis's clamped speed-mode law (K = 5, n = 1.5,
// D = 350); after the 5 V step the contact unloads slowly near grazing. Without stopping at the
// clamp kink, rtol 1e-8 kept the contact ~25 ms too long and the link rate then differed from
// the rtol 1e-11 run by 2.1 °/s; with it both agree to the tolerance level.
TEST(ContactKinks, NearGrazingUnloadSeparatesOnTimeAtDefaultTolerance) {
  cp::PlantModel model;
  model.drive = cp::DriveModel::thesis_speed_mode();
  model.link.inertia_kg_m2 = 5e-3;
  model.link.ground_viscous_n_m_s_per_rad = 1e-4;
  cp::TorsionalClearance joint;
  joint.half_play_rad = clearshape::deg_to_rad(0.5);
  joint.law = cp::ContactLaw::thesis_speed_mode(cp::DampingPolicy::clamped);
  joint.joint_friction.viscous = 1e-3;
  model.joint = joint;
  const auto run = [&](double rtol) {
    cp::SimulationOptions o;
    o.duration_s = 2.5;
    o.solver.relative_tolerance = rtol;
    o.solver.angle_tolerance_rad = 1e-11;
    o.solver.rate_tolerance_rad_s = 1e-9;
    o.initial.relative_angle_rad = joint.half_play_rad;
    return cp::simulate(model, cp::Command::step(0.5, 5.0), o);
  };
  const cp::Simulation loose = run(1e-8);
  const cp::Simulation tight = run(1e-11);
  ASSERT_EQ(loose.size(), tight.size());
  double worst_deg_s = 0.0;
  for (std::size_t k = 0; k < loose.size(); ++k) {
    worst_deg_s = std::max(worst_deg_s, std::abs(clearshape::rad_to_deg(loose.link_rate_rad_s[k] -
                                                                        tight.link_rate_rad_s[k])));
  }
  EXPECT_LT(worst_deg_s, 1e-3);  // the link rate peaks at ~140 °/s
  // same contact history; a near-grazing separation time is ill-conditioned (δ is tangent to
  // 0), 0.1 ms here against the 25 ms of the unstopped kink
  ASSERT_EQ(loose.events.size(), tight.events.size());
  for (std::size_t i = 0; i < loose.events.size(); ++i) {
    EXPECT_EQ(loose.events[i].kind, tight.events[i].kind);
    EXPECT_NEAR(loose.events[i].time_s, tight.events[i].time_s, 1e-4) << "event " << i;
  }
}
