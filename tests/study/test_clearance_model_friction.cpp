// The joint friction of study::ClearanceModel (thesis Eq. 2.9 as a bearing torque on the
// link–motor relative rate, τ = −c·tanh(φ̇/v_t) − b·φ̇), checked against Newton's law for the
// link in free flight: with the motor at rest and the link between the flanks, J·dω/dt must equal
// the friction torque at the link's own rate — computed here from the recorded rate, not by the
// library. And a model without friction keeps its old response exactly (friction 0 is the default).
#include <cmath>
#include <algorithm>
#include <cstddef>
#include <string>

#include <gtest/gtest.h>

#include "clearshape/core/units.hpp"
#include "clearshape/study/model.hpp"
#include "support/clearance_fixtures.hpp"

namespace clearshape::study {
namespace {

constexpr double kTs = 1e-3;

// The thesis's position drive (Eq. 4.2, §4.2) and a play of 20°: a link thrown off its rear
// flank by a 10° step coasts for a long, clean stretch before reaching the front flank.
ClearanceModel coasting_model(double coulomb_n_m, double viscous) {
  ClearanceModel m = testing::thesis_position_clearance_model();
  m.play_rad = deg_to_rad(20.0);
  m.stiffness = 1e4;
  m.exponent = 1.5;
  m.damping = 1.0;
  m.coulomb_n_m = coulomb_n_m;
  m.viscous_n_m_s_per_rad = viscous;
  return m;
}

UniformSeries step(double amplitude_deg, double duration_s) {
  UniformSeries u;
  u.sample_time_s = kTs;
  u.values.assign(static_cast<std::size_t>(duration_s / kTs) + 1, 0.0);
  for (std::size_t k = 50; k < u.values.size(); ++k) u.values[k] = amplitude_deg;
  return u;
}

TEST(ClearanceModelFriction, FreeFlightDeceleratesAsNewtonsLawWithEq29) {
  const double c = 0.05, b = 2e-3, J = 5e-3;
  const ClearanceModel m = coasting_model(c, b);
  const double duration = 0.6;
  // Start on the rear flank (φ = −β): the motor's step carries the link, then leaves it.
  const ModelResponse r = simulate_drive_command(m, step(10.0, duration), duration, -1.0);
  const double beta_deg = 10.0;
  int checked = 0;
  double worst = 0.0;
  for (std::size_t k = 1; k + 1 < r.time_s.size(); ++k) {
    const double phi_deg = r.link_angle_deg[k] - beta_deg - r.motor_angle_deg[k];  // link started at −β
    const bool free = std::abs(phi_deg) < beta_deg - 0.5;
    const bool motor_at_rest = std::abs(r.motor_rate_deg_s[k]) < 1e-3;
    const double w = deg_to_rad(r.link_rate_deg_s[k]);
    if (!free || !motor_at_rest || std::abs(w) < 0.05) continue;  // tanh saturated: |φ̇| ≥ 50 v_t
    const double accel = deg_to_rad(r.link_rate_deg_s[k + 1] - r.link_rate_deg_s[k - 1]) / (2.0 * kTs);
    const double expected = (-c * std::tanh(w / 1e-3) - b * w) / J;  // J dω/dt = τ_f (Eq. 2.9 + viscous)
    worst = std::max(worst, std::abs(accel - expected) / std::abs(expected));
    ++checked;
  }
  EXPECT_GT(checked, 50);  // a real coasting stretch was checked
  EXPECT_LT(worst, 1e-3);
}

TEST(ClearanceModelFriction, ZeroFrictionIsTheFrictionlessModel) {
  ClearanceModel m = coasting_model(0.0, 0.0);
  m.play_rad = deg_to_rad(1.0);
  const ModelResponse a = simulate_drive_command(m, step(20.0, 0.5), 0.5);
  m.coulomb_n_m = 2e-3;
  const ModelResponse f = simulate_drive_command(m, step(20.0, 0.5), 0.5);
  ASSERT_EQ(a.link_rate_deg_s.size(), f.link_rate_deg_s.size());
  double diff = 0.0;
  for (std::size_t k = 0; k < a.link_rate_deg_s.size(); ++k) {
    diff = std::max(diff, std::abs(a.link_rate_deg_s[k] - f.link_rate_deg_s[k]));
  }
  EXPECT_GT(diff, 1e-3);  // friction changes the free flight in the play
  EXPECT_EQ(ClearanceModel{}.coulomb_n_m, 0.0);
  EXPECT_EQ(ClearanceModel{}.viscous_n_m_s_per_rad, 0.0);
}

TEST(ClearanceModelFriction, NegativeFrictionIsRejectedNamingTheField) {
  ClearanceModel m = coasting_model(-1e-3, 0.0);
  try {
    simulate_drive_command(m, step(5.0, 0.2), 0.2);
    FAIL() << "negative Coulomb torque accepted";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("coulomb"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace clearshape::study
