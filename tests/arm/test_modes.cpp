// The arm's linearised modes (arm/modes.hpp) against tests/golden/gen_arm_modes.py: scara-2's
// closed-form M(q) with scipy.linalg.eigh(K, M), cross-checked there against the eigenvalues of
// the first-order system. Frequencies, damping ratios and modal shares to 1e-9 relative.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "clearshape/arm/modes.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/table.hpp"
#include "support/paths.hpp"

namespace clearshape::arm {
namespace {

TEST(ArmModes, ScaraModesMatchScipyEigh) {
  const auto t = io::read_table(testing::golden_path("arm_scara_modes.csv"));
  const ArmModel arm = builtin_arm("scara-2");
  ASSERT_EQ(t.rows(), 27u);
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const ArmModes m = joint_modes(arm, Eigen::Vector2d(0.7, t.column("q2_rad")[r]));  // M does not depend on q1
    for (int k = 0; k < 2; ++k) {
      const std::string s = std::to_string(k + 1);
      EXPECT_NEAR(m.natural_frequency_rad_s(k) / (2 * std::numbers::pi) / t.column("f" + s + "_hz")[r], 1.0, 1e-9) << r;
      EXPECT_NEAR(m.damping_ratio(k) / t.column("zeta" + s)[r], 1.0, 1e-9) << r;
      for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(m.share(k, i), t.column("share_" + s + "_" + std::to_string(i + 1))[r], 1e-9) << r;
      }
    }
    for (int i = 0; i < 2; ++i) {  // the dominant mode is the one with the largest share
      const int d = m.dominant_mode[static_cast<std::size_t>(i)];
      EXPECT_GE(m.share(d, i), m.share(1 - d, i));
      EXPECT_EQ(m.joint_mode(i).natural_frequency_rad_s, m.natural_frequency_rad_s(d));
    }
  }
}

TEST(ArmModes, WorkspaceCentreAndRefusals) {
  const ArmModel arm = builtin_arm("scara-2");
  EXPECT_EQ(workspace_centre(arm), Eigen::Vector2d(0.0, 0.0));  // limits ±2.6 rad
  EXPECT_THROW(joint_modes(arm, Eigen::Vector3d(0, 0, 0)), InvalidArgument);
  EXPECT_THROW(joint_modes(arm, Eigen::Vector2d(0, NAN)), InvalidArgument);
  ArmModel loose = arm;
  loose.joints[1].law = plant::ContactLaw::hertz_dashpot(1e4, 1.5, 0.0, plant::DampingPolicy::raw);
  // Hertz n = 1.5: the tangent stiffness 1.5 K δ^0.5 depends on the penetration
  const ArmModes a = joint_modes(loose, Eigen::Vector2d(0, 0), {.flank_penetration_rad = 1e-4});
  EXPECT_NEAR(a.stiffness_n_m_per_rad(1), 1.5e4 * std::sqrt(1e-4), 1e-9);
  EXPECT_THROW(joint_modes(loose, Eigen::Vector2d(0, 0), {.flank_penetration_rad = 0.0}), InvalidArgument);
}

}  // namespace
}  // namespace clearshape::arm
