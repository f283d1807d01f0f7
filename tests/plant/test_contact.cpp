// Contact-law building blocks: Hertz stiffness from materials (T13), χ(e), ζ(e), the impulse
// solve (Eq. 2.13–2.16), friction.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "clearshape/core/error.hpp"
#include "clearshape/plant/contact_law.hpp"
#include "clearshape/plant/friction.hpp"
#include "clearshape/plant/hertz.hpp"
#include "clearshape/plant/impact.hpp"

namespace cp = clearshape::plant;

// T13: (4/3) E* √R* equals the thesis form 4/(3π(h₁+h₂)) √R; steel journal R_J = 9.5 mm in a
// bearing R_B = 10 mm: R* = 0.19 m (internal), E* = 113.7 GPa, K = 6.6102e10 N/m^1.5.
TEST(Hertz, MaterialsGiveTheReferenceStiffness) {
  const auto steel = cp::Material::steel();
  const double r = cp::effective_radius_internal(9.5e-3, 10e-3);
  EXPECT_NEAR(r, 0.19, 1e-15);
  EXPECT_NEAR(cp::effective_modulus_pa(steel, steel), 113.736e9, 0.001e9);
  const double k = cp::hertz_stiffness(steel, steel, r);
  const double k_thesis = cp::hertz_stiffness_thesis(cp::compliance_parameter(steel),
                                                     cp::compliance_parameter(steel), r);
  EXPECT_NEAR(k / k_thesis, 1.0, 1e-12);
  EXPECT_NEAR(k, 6.6102e10, 0.0001e10);
  // the common bug (R_J R_B/(R_J + R_B)) is 39 times smaller in R*
  EXPECT_NEAR(cp::effective_radius_external(9.5e-3, 10e-3), 9.5e-3 * 10e-3 / 19.5e-3, 1e-18);
  EXPECT_THROW((void)cp::effective_radius_internal(10e-3, 9.5e-3), clearshape::InvalidArgument);
  // a force law at radius r as a torque law: K_ang = K r^(n+1), D_ang = D r²
  EXPECT_NEAR(cp::torsional_stiffness(k, 1.5, 0.01), k * std::pow(0.01, 2.5), 1e-3);
  EXPECT_DOUBLE_EQ(cp::torsional_damping(300.0, 0.02), 0.12);
}

TEST(ContactLaw, FactorsAndDampingRatio) {
  EXPECT_DOUBLE_EQ(cp::hysteresis_factor(cp::Hysteresis::hunt_crossley, 0.5), 0.75);
  EXPECT_DOUBLE_EQ(cp::hysteresis_factor(cp::Hysteresis::lankarani_nikravesh, 0.5), 0.5625);
  EXPECT_DOUBLE_EQ(cp::hysteresis_factor(cp::Hysteresis::flores, 0.5), 1.6);
  EXPECT_DOUBLE_EQ(cp::hysteresis_factor(cp::Hysteresis::gonthier, 0.5), 1.5);
  EXPECT_DOUBLE_EQ(cp::hysteresis_factor(cp::Hysteresis::hu_guo, 0.5), 1.5);
  EXPECT_DOUBLE_EQ(cp::kelvin_voigt_damping_ratio(1.0), 0.0);
  const double l = std::log(0.5);
  EXPECT_DOUBLE_EQ(cp::kelvin_voigt_damping_ratio(0.5), -l / std::sqrt(std::numbers::pi * std::numbers::pi + l * l));
  EXPECT_THROW((void)cp::hysteresis_factor(cp::Hysteresis::flores, 0.0), clearshape::InvalidArgument);
  EXPECT_THROW((void)cp::ContactLaw::hertz_dashpot(-1.0, 1.5, 1.0), clearshape::InvalidArgument);
  EXPECT_THROW((void)cp::ContactLaw::hertz_dashpot(1.0, 0.5, 1.0), clearshape::InvalidArgument);
}

TEST(ContactLaw, ThesisPresets) {
  const auto pos = cp::ContactLaw::thesis_position_mode();
  EXPECT_EQ(pos.stiffness(), 10000.0);
  EXPECT_EQ(pos.damping(), 300.0);
  EXPECT_EQ(pos.exponent(), 1.5);
  EXPECT_EQ(pos.policy(), cp::DampingPolicy::raw);
  const auto spd = cp::ContactLaw::thesis_speed_mode(cp::DampingPolicy::clamped);
  EXPECT_EQ(spd.stiffness(), 5.0);
  EXPECT_EQ(spd.damping(), 350.0);
  EXPECT_EQ(spd.policy(), cp::DampingPolicy::clamped);
}

TEST(ContactLaw, ForcesAndDerivatives) {
  const cp::ContactMemory none{};
  const auto law = cp::ContactLaw::hertz_dashpot(1e4, 1.5, 300.0, cp::DampingPolicy::raw);
  const double d = 1e-3;
  const double v = -0.05;
  const auto f = law.evaluate(d, v, none);
  EXPECT_DOUBLE_EQ(f.force, 1e4 * std::pow(d, 1.5) + 300.0 * v);  // thesis Eq. 4.3
  EXPECT_LT(f.force, 0.0);                                         // raw pulls
  EXPECT_EQ(law.evaluate(-1e-6, 1.0, none).force, 0.0);
  // derivatives by central differences
  const double h = 1e-9;
  EXPECT_NEAR(f.d_penetration, (law.evaluate(d + h, v, none).force - law.evaluate(d - h, v, none).force) / (2 * h), 1e-3);
  EXPECT_DOUBLE_EQ(f.d_rate, 300.0);
  const auto clamped = cp::ContactLaw::hertz_dashpot(1e4, 1.5, 300.0, cp::DampingPolicy::clamped);
  EXPECT_EQ(clamped.evaluate(d, v, none).force, 0.0);
  // hysteresis: K δⁿ (1 + χ δ̇/δ̇⁻) with δ̇⁻ latched; χ = 0 when δ̇⁻ is below the floor
  const auto hc = cp::ContactLaw::hysteresis(cp::Hysteresis::hunt_crossley, 2.0, 1.5, 0.5, 1e-3);
  const cp::ContactMemory latched{hc.latch_approach_rate(0.4), false};
  EXPECT_DOUBLE_EQ(hc.evaluate(0.01, 0.2, latched).force, 2.0 * std::pow(0.01, 1.5) * (1.0 + 0.75 * 0.2 / 0.4));
  EXPECT_EQ(hc.latch_approach_rate(1e-4), 0.0);
  EXPECT_DOUBLE_EQ(hc.evaluate(0.01, 0.2, cp::ContactMemory{0.0, false}).force, 2.0 * std::pow(0.01, 1.5));
  EXPECT_EQ(hc.evaluate(0.01, -10.0, latched).force, 0.0);  // clamped at 0
  EXPECT_DOUBLE_EQ(hc.potential(0.01), 2.0 * std::pow(0.01, 2.5) / 2.5);
}

// T9: impulse–momentum (Eq. 2.13–2.15): normal velocity reversed and scaled by e; momentum of
// a free–free two-body impact conserved.
TEST(Impact, ImpulseSolveConservesMomentum) {
  Eigen::MatrixXd m = Eigen::MatrixXd::Zero(2, 2);
  m(0, 0) = 2.0;
  m(1, 1) = 3.0;
  Eigen::VectorXd w(2);
  w << 1.0, -1.0;  // δ̇ = v₁ − v₂
  Eigen::VectorXd u(2);
  u << 1.5, -0.5;
  for (double e : {0.0, 0.4, 1.0}) {
    const auto r = cp::solve_impulse(m, w, u, e);
    EXPECT_NEAR(w.dot(r.velocity_after), -e * w.dot(u), 1e-14);
    EXPECT_NEAR((m * r.velocity_after).sum(), (m * u).sum(), 1e-14);
    // Eq. 2.13: M u⁺ + g'ᵀ s_N = M u⁻ with s_N = −P_N
    EXPECT_NEAR((m * (r.velocity_after - u) - w * r.impulse).norm(), 0.0, 1e-14);
    const double ke0 = 0.5 * u.dot(m * u);
    const double ke1 = 0.5 * r.velocity_after.dot(m * r.velocity_after);
    const double m_eff = 1.0 / (1.0 / 2.0 + 1.0 / 3.0);
    EXPECT_NEAR(ke0 - ke1, 0.5 * m_eff * (1 - e * e) * 4.0, 1e-12);  // T8: ½ m_eff (1−e²) v₀²
  }
}

// Eq. 2.16 equals the elastic closed form K δ_max^n with δ_max = ((n+1) m v²/(2K))^(1/(n+1)).
TEST(Impact, PeakForceEquation216) {
  const double k = 6.61e10, m = 0.2, v = 0.5;
  const double d_max = std::pow(2.5 * m * v * v / (2.0 * k), 1.0 / 2.5);
  EXPECT_NEAR(cp::peak_contact_force(k, 1.5, m, m * v) / (k * std::pow(d_max, 1.5)), 1.0, 1e-12);
  EXPECT_NEAR(cp::peak_contact_force(k, 1.5, m, m * v), 4033.0, 1.0);  // B2 steel example
}

TEST(Friction, RegularizedCoulombStribeckViscous) {
  cp::Friction f;
  f.viscous = 0.1;
  f.coulomb = 0.5;
  f.regularization_rate = 1e-3;
  EXPECT_NEAR(f.evaluate(1.0).force, -0.1 - 0.5, 1e-12);
  EXPECT_NEAR(f.evaluate(-1.0).force, 0.1 + 0.5, 1e-12);
  EXPECT_EQ(f.evaluate(0.0).force, 0.0);
  f.static_level = 0.8;
  f.stribeck_rate = 0.01;
  EXPECT_NEAR(f.evaluate(0.005).force, -0.1 * 0.005 - (0.5 + 0.3 * std::exp(-0.25)) * std::tanh(5.0), 1e-12);
  const double h = 1e-8;
  for (double v : {-0.02, 0.0004, 0.003, 0.5}) {
    EXPECT_NEAR(f.evaluate(v).d_rate, (f.evaluate(v + h).force - f.evaluate(v - h).force) / (2 * h), 1e-4);
  }
  cp::CoulombContactFriction mu{0.2, 1e-3};
  EXPECT_NEAR(mu.factor(0.1).force, 0.2, 1e-12);  // Eq. 2.9: μ sgn(v_T) for |v_T| ≫ v_t
}
