// Single-impact oracles (docs/design.md §5).
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

// T2: effective restitution of the hysteresis family, Hertz n = 1.5 (docs/design.md §5
// table, computed by the reference with RK4 h = 5e-5 in normalised units), ± 0.002.
struct HysteresisRow {
  cp::Hysteresis model;
  double e_eff[7];
};

TEST(Restitution, HysteresisLawsMatchReferenceTable) {
  const double nominal[7] = {0.10, 0.30, 0.50, 0.70, 0.80, 0.90, 0.95};
  const HysteresisRow rows[] = {
      {cp::Hysteresis::hunt_crossley, {0.516, 0.581, 0.663, 0.768, 0.833, 0.909, 0.952}},
      {cp::Hysteresis::herbert_mcwhannell, {0.491, 0.520, 0.594, 0.723, 0.807, 0.901, 0.950}},
      {cp::Hysteresis::lee_wang, {0.687, 0.739, 0.799, 0.869, 0.909, 0.952, 0.976}},
      {cp::Hysteresis::lankarani_nikravesh, {0.665, 0.684, 0.725, 0.796, 0.847, 0.913, 0.954}},
      {cp::Hysteresis::gonthier, {0.101, 0.304, 0.488, 0.670, 0.768, 0.876, 0.936}},
      {cp::Hysteresis::zhiying_qishao, {0.217, 0.327, 0.483, 0.680, 0.787, 0.896, 0.949}},
      {cp::Hysteresis::flores, {0.069, 0.256, 0.470, 0.683, 0.789, 0.894, 0.947}},
      {cp::Hysteresis::hu_guo, {0.074, 0.271, 0.488, 0.697, 0.799, 0.900, 0.950}},
  };
  for (const auto& row : rows) {
    for (int i = 0; i < 7; ++i) {
      const auto law = cp::ContactLaw::hysteresis(row.model, 1.0, 1.5, nominal[i]);
      const auto r = cp::single_impact(law, 1.0, 1.0, tight());
      EXPECT_TRUE(r.separated);
      EXPECT_NEAR(r.restitution, row.e_eff[i], 0.002)
          << cp::to_string(row.model) << " e = " << nominal[i];
    }
  }
}

// T2: e_eff of a hysteresis law does not depend on K, m or v₀ (scaled ×10 and ×0.1), ± 1e-4.
TEST(Restitution, HysteresisInvariantToScale) {
  for (auto model : {cp::Hysteresis::hunt_crossley, cp::Hysteresis::lankarani_nikravesh,
                     cp::Hysteresis::flores}) {
    const auto base = cp::single_impact(cp::ContactLaw::hysteresis(model, 1.0, 1.5, 0.5), 1.0, 1.0,
                                        tight());
    for (double f : {10.0, 0.1}) {
      const auto k = cp::single_impact(cp::ContactLaw::hysteresis(model, f, 1.5, 0.5), 1.0, 1.0,
                                       tight());
      const auto m = cp::single_impact(cp::ContactLaw::hysteresis(model, 1.0, 1.5, 0.5), f, 1.0,
                                       tight());
      const auto v = cp::single_impact(cp::ContactLaw::hysteresis(model, 1.0, 1.5, 0.5, 1e-9), 1.0,
                                       f, tight());
      EXPECT_NEAR(k.restitution, base.restitution, 1e-4) << cp::to_string(model) << " K x" << f;
      EXPECT_NEAR(m.restitution, base.restitution, 1e-4) << cp::to_string(model) << " m x" << f;
      EXPECT_NEAR(v.restitution, base.restitution, 1e-4) << cp::to_string(model) << " v x" << f;
    }
  }
}

// T3: thesis law F = K δ^1.5 + D δ̇; e depends only on z = D (m v₀²/K)^(2/5)/(m v₀)
// (docs/design.md §5), ± 0.003. With m = K = v₀ = 1, z = D.
TEST(Restitution, ThesisLawMatchesReferenceTable) {
  const double z[8] = {0.01, 0.03, 0.10, 0.20, 0.30, 0.50, 1.0, 2.0};
  const double raw[7] = {0.982, 0.947, 0.833, 0.689, 0.563, 0.357, 0.041};
  const double clamp[8] = {0.983, 0.949, 0.845, 0.721, 0.621, 0.468, 0.252, 0.095};
  const double msl[8] = {0.983, 0.951, 0.856, 0.752, 0.673, 0.561, 0.406, 0.269};
  for (int i = 0; i < 8; ++i) {
    const auto c = cp::single_impact(
        cp::ContactLaw::hertz_dashpot(1.0, 1.5, z[i], cp::DampingPolicy::clamped), 1.0, 1.0, tight());
    EXPECT_NEAR(c.restitution, clamp[i], 0.003) << "clamped z = " << z[i];
    EXPECT_GE(c.min_force, 0.0) << "the clamped law never pulls";
    const auto b = cp::single_impact(
        cp::ContactLaw::hertz_dashpot(1.0, 1.5, z[i], cp::DampingPolicy::bounded), 1.0, 1.0, tight());
    EXPECT_NEAR(b.restitution, msl[i], 0.003) << "bounded z = " << z[i];
    EXPECT_GE(b.min_force, 0.0);
    const auto r = cp::single_impact(
        cp::ContactLaw::hertz_dashpot(1.0, 1.5, z[i], cp::DampingPolicy::raw), 1.0, 1.0, tight());
    if (i < 7) {
      EXPECT_TRUE(r.separated);
      EXPECT_NEAR(r.restitution, raw[i], 0.003) << "raw z = " << z[i];
      if (i >= 2) {
        EXPECT_LT(r.min_force, 0.0) << "the raw law pulls near separation, z = " << z[i];
      }
    } else {
      EXPECT_FALSE(r.separated) << "the raw law sticks at z = 2";
      EXPECT_EQ(r.restitution, 0.0);
    }
  }
}

// T3: the bounded (MSL ElastoBacklash) law is continuous at onset (F → 0 as δ → 0) whereas the
// clamped and raw laws jump by D·δ̇⁻.
TEST(Restitution, BoundedLawContinuousAtOnset) {
  const cp::ContactMemory none{};
  const double d = 300.0;
  const auto bounded = cp::ContactLaw::hertz_dashpot(1e4, 1.5, d, cp::DampingPolicy::bounded);
  const auto clamped = cp::ContactLaw::hertz_dashpot(1e4, 1.5, d, cp::DampingPolicy::clamped);
  for (double delta : {1e-6, 1e-9, 1e-12}) {
    const double limit = 2.0 * 1e4 * std::pow(delta, 1.5);
    EXPECT_LE(bounded.evaluate(delta, 1.0, none).force, limit * (1 + 1e-12));
    EXPECT_NEAR(clamped.evaluate(delta, 1.0, none).force, d, d * 1e-3);
  }
  EXPECT_EQ(bounded.evaluate(0.0, 1.0, none).force, 0.0);
  EXPECT_TRUE(clamped.jumps_at_onset());
  EXPECT_FALSE(bounded.jumps_at_onset());
}

// T4 / B2: elastic Hertz impact in closed form (χ = 0 ⇔ e = 1):
// δ_max = (5 m v₀²/(4K))^(2/5), F_max = K δ_max^(3/2), t_c = 2.9432 δ_max/v₀ (normalised:
// δ_max = 1.09336, F_max = 1.14326, t_c = 3.21807).
TEST(Restitution, ElasticHertzImpactClosedForm) {
  const auto law = cp::ContactLaw::hertz_dashpot(1.0, 1.5, 0.0, cp::DampingPolicy::raw);
  const auto r = cp::single_impact(law, 1.0, 1.0, tight());
  ASSERT_TRUE(r.separated);
  EXPECT_NEAR(r.restitution, 1.0, 1e-6);
  const double d_max = std::pow(1.25, 0.4);
  EXPECT_NEAR(r.max_penetration / d_max, 1.0, 1e-5);
  EXPECT_NEAR(r.max_force / std::pow(d_max, 1.5), 1.0, 1e-5);
  EXPECT_NEAR(r.contact_time_s / 3.21807, 1.0, 1e-5);
  EXPECT_NEAR(r.dissipated_energy, 0.0, 1e-8 * 0.5);
  // steel example (B2): m = 0.2 kg, v₀ = 0.5 m/s, K = 6.61e10 N/m^1.5
  const auto steel = cp::single_impact(
      cp::ContactLaw::hertz_dashpot(6.61e10, 1.5, 0.0, cp::DampingPolicy::raw), 0.2, 0.5, tight());
  EXPECT_NEAR(steel.max_penetration, 1.550e-5, 0.001e-5);
  EXPECT_NEAR(steel.max_force, 4033.0, 1.0);
  EXPECT_NEAR(steel.contact_time_s, 9.12e-5, 0.01e-5);
}

// The non-stiff Adams option on the elastic Hertz impact.
TEST(Restitution, AdamsIntegratorOnElasticImpact) {
  auto o = tight();
  o.integrator = cp::Integrator::adams;
  const auto r = cp::single_impact(cp::ContactLaw::hertz_dashpot(1.0, 1.5, 0.0, cp::DampingPolicy::raw),
                                   1.0, 1.0, o);
  ASSERT_TRUE(r.separated);
  EXPECT_NEAR(r.restitution, 1.0, 1e-6);
  EXPECT_NEAR(r.contact_time_s / 3.21807, 1.0, 1e-5);
}

// Thesis Eq. 2.2–2.3 Kelvin–Voigt (load with c, unload with e·c): the rebound returns √e.
TEST(Restitution, ThesisKelvinVoigtReturnsSquareRootOfE) {
  for (double e : {0.25, 0.64}) {
    const auto r = cp::single_impact(cp::ContactLaw::kelvin_voigt_thesis(1e4, e), 2.0, 0.3, tight());
    ASSERT_TRUE(r.separated);
    EXPECT_NEAR(r.restitution, std::sqrt(e), 1e-6) << "e = " << e;
    // dissipated per impact: ½ m (1 − e_eff²) v₀² (T8)
    EXPECT_NEAR(r.dissipated_energy, 0.5 * 2.0 * (1.0 - e) * 0.09, 1e-8);
  }
}

// T3: e of the thesis law depends on K, D, m, v₀ only through z; the thesis calibrations are
// deep in the sticking regime for any plausible link (J = 1e-3 kg·m², ω₀ = 1 rad/s).
TEST(Restitution, ThesisLawDependsOnlyOnZ) {
  EXPECT_DOUBLE_EQ(cp::dashpot_group(1.0, 1.5, 0.3, 1.0, 1.0), 0.3);
  const auto base = cp::single_impact(
      cp::ContactLaw::hertz_dashpot(1.0, 1.5, 0.3, cp::DampingPolicy::clamped), 1.0, 1.0, tight());
  // K ×100, m ×0.5, v₀ ×3 with D chosen to keep z = 0.3
  const double k = 100.0, m = 0.5, v = 3.0;
  const double d = 0.3 / cp::dashpot_group(k, 1.5, 1.0, m, v);
  ASSERT_NEAR(cp::dashpot_group(k, 1.5, d, m, v), 0.3, 1e-14);
  const auto scaled = cp::single_impact(
      cp::ContactLaw::hertz_dashpot(k, 1.5, d, cp::DampingPolicy::clamped), m, v, tight());
  EXPECT_NEAR(scaled.restitution, base.restitution, 1e-6);
  EXPECT_NEAR(cp::dashpot_group(10000.0, 1.5, 300.0, 1e-3, 1.0), 475.468, 1e-3);  // ≫ 2: sticks
  EXPECT_NEAR(cp::dashpot_group(5.0, 1.5, 350.0, 1e-3, 1.0), 11600.59, 1e-2);
  EXPECT_NEAR(cp::dashpot_group(10000.0, 1.5, 300.0, 1e-4, 1.0), 1.9e3, 0.05e3);  // §3.4 example
}
