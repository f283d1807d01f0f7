// White-box check of the torsional joint's analytic Jacobian (including the rows of the energy
// integrals) against central differences of its right-hand side, in each contact mode.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "../../src/plant/torsional_system.hpp"
#include "clearshape/plant/joint.hpp"

namespace cp = clearshape::plant;
namespace cd = clearshape::plant::detail;

namespace {
void check_jacobian(cd::TorsionalSystem& sys, std::vector<double> y, const char* what) {
  const int n = sys.size;
  std::vector<double> jac(static_cast<std::size_t>(n * n));
  ASSERT_EQ(sys.jacobian(0.3, y.data(), jac.data()), 0);
  std::vector<double> fp(static_cast<std::size_t>(n)), fm(static_cast<std::size_t>(n));
  for (int j = 0; j < n; ++j) {
    const double h = 1e-7 * std::max(1e-3, std::abs(y[j]));
    std::vector<double> yp = y, ym = y;
    yp[j] += h;
    ym[j] -= h;
    ASSERT_EQ(sys.rhs(0.3, yp.data(), fp.data()), 0);
    ASSERT_EQ(sys.rhs(0.3, ym.data(), fm.data()), 0);
    for (int i = 0; i < n; ++i) {
      const double fd = (fp[i] - fm[i]) / (2.0 * h);
      const double an = jac[static_cast<std::size_t>(i + n * j)];
      EXPECT_NEAR(an, fd, 1e-5 * (std::abs(fd) + 1.0)) << what << ": d f" << i << " / d y" << j;
    }
  }
}
}  // namespace

TEST(Jacobian, TorsionalAnalyticMatchesDifferences) {
  cp::PlantModel m;
  m.drive = cp::DriveModel::thesis_position_mode();
  m.link.inertia_kg_m2 = 2e-3;
  m.link.mass_kg = 0.2;
  m.link.com_distance_m = 0.05;
  m.link.axis_tilt_rad = 1.0;
  m.link.ground_viscous_n_m_s_per_rad = 1e-3;
  cp::TorsionalClearance j;
  j.half_play_rad = 0.01;
  j.law = cp::ContactLaw::hertz_dashpot(1e4, 1.5, 3.0, cp::DampingPolicy::clamped);
  j.joint_friction.coulomb = 2e-3;
  j.joint_friction.viscous = 1e-4;
  j.joint_friction.static_level = 3e-3;
  j.joint_friction.regularization_rate = 0.05;
  m.joint = j;
  const cp::SolverOptions o;
  cd::TorsionalSystem sys(m, o);
  sys.input.held = 5.0;
  const int nd = m.drive.order();
  std::vector<double> y(static_cast<std::size_t>(sys.size), 0.0);
  for (int i = 0; i < nd; ++i) y[static_cast<std::size_t>(i)] = 0.3 * (i + 1) - 0.2;
  y[static_cast<std::size_t>(nd)] = 0.0123;      // φ: 2.3 mrad into the + stop
  y[static_cast<std::size_t>(nd + 1)] = 0.7;     // ω_link
  sys.mode = cp::ContactMode::contact;
  check_jacobian(sys, y, "contact");
  y[static_cast<std::size_t>(nd)] = 0.004;       // inside the play
  sys.mode = cp::ContactMode::free;
  check_jacobian(sys, y, "free");
  y[static_cast<std::size_t>(nd)] = 0.01;        // at the stop, locked
  sys.mode = cp::ContactMode::locked;
  check_jacobian(sys, y, "locked");
}
