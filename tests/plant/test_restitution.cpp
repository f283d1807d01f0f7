// Single-impact oracles (reference/clearance_sim.md §7 T1–T4, §3.3–3.4, B1–B2).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "clearshape/plant/contact_law.hpp"
#include "clearshape/plant/simulation.hpp"

namespace cp = clearshape::plant;

namespace {
cp::SolverOptions tight() {
  cp::SolverOptions o;
  o.relative_tolerance = 1e-10;
  return o;
}
}  // namespace

// T1: raw Kelvin–Voigt with ζ(e) returns e exactly; contact time π/ω_d.
TEST(Restitution, KelvinVoigtRecoversRestitutionExactly) {
  const double m = 1.0;
  const double k = 1e6;
  for (double e : {0.1, 0.5, 0.9}) {
    const auto law = cp::ContactLaw::kelvin_voigt_restitution(k, e, m, cp::DampingPolicy::raw);
    const auto r = cp::single_impact(law, m, 1.0, tight());
    ASSERT_TRUE(r.separated);
    EXPECT_NEAR(r.restitution, e, 1e-6) << "e = " << e;
    const double zeta = cp::kelvin_voigt_damping_ratio(e);
    const double wd = std::sqrt(k / m) * std::sqrt(1.0 - zeta * zeta);
    EXPECT_NEAR(r.contact_time_s / (std::numbers::pi / wd), 1.0, 1e-6) << "e = " << e;
  }
}
