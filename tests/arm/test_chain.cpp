// The arm's rigid-body part against independent references: the closed-form M(q) and tool
// position of scara-2 and the gravity torque of vertical-2 from tests/golden/gen_arm_scara.py;
// malformed and unsupported URDFs refused naming the file, the element and the reason.
#include <gtest/gtest.h>

#include <string>

#include "clearshape/arm/arm.hpp"
#include "clearshape/core/error.hpp"
#include "clearshape/io/table.hpp"
#include "support/paths.hpp"

namespace clearshape::arm {
namespace {

using clearshape::testing::golden_path;

TEST(ArmChain, ScaraMassMatrixAndToolMatchTheClosedForm) {
  const ArmModel arm = builtin_arm("scara-2");
  ChainWorkspace ws(arm.chain);
  const io::Table t = io::read_table(golden_path("arm_scara_mass.csv"));
  ASSERT_EQ(t.rows(), 33u);
  Eigen::MatrixXd m;
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const Eigen::Vector2d q(t.column("q1_rad")[r], t.column("q2_rad")[r]);
    ws.mass_matrix(q, m);
    const double m11 = t.column("m11_kg_m2")[r], m12 = t.column("m12_kg_m2")[r], m22 = t.column("m22_kg_m2")[r];
    EXPECT_NEAR(m(0, 0), m11, 1e-9 * std::abs(m11)) << "row " << r;
    EXPECT_NEAR(m(0, 1), m12, 1e-9 * m11) << "row " << r;  // m12 crosses 0: relative to the matrix
    EXPECT_NEAR(m(1, 0), m12, 1e-9 * m11) << "row " << r;
    EXPECT_NEAR(m(1, 1), m22, 1e-9 * std::abs(m22)) << "row " << r;
    const Eigen::Vector3d tip = ws.tip_position_m(q);
    EXPECT_NEAR(tip.x(), t.column("tool_x_m")[r], 1e-12);
    EXPECT_NEAR(tip.y(), t.column("tool_y_m")[r], 1e-12);
    EXPECT_NEAR(tip.z(), t.column("tool_z_m")[r], 1e-12);
    Eigen::VectorXd g;
    ws.gravity_torque(q, g);  // gravity along the joint axes: no torque
    EXPECT_NEAR(g.norm(), 0.0, 1e-12);
  }
}

TEST(ArmChain, VerticalGravityTorqueMatchesTheGradientOfThePotential) {
  const ArmModel arm = builtin_arm("vertical-2");
  ChainWorkspace ws(arm.chain);
  const io::Table t = io::read_table(golden_path("arm_vertical_gravity.csv"));
  Eigen::VectorXd g;
  for (std::size_t r = 0; r < t.rows(); ++r) {
    const Eigen::Vector2d q(t.column("q1_rad")[r], t.column("q2_rad")[r]);
    ws.gravity_torque(q, g);
    EXPECT_NEAR(g(0), t.column("g1_n_m")[r], 1e-9 * (1.0 + std::abs(g(0)))) << "row " << r;
    EXPECT_NEAR(g(1), t.column("g2_n_m")[r], 1e-9 * (1.0 + std::abs(g(1)))) << "row " << r;
  }
}

std::string two_link_urdf(const std::string& second_joint_type) {
  return R"(<robot name="r"><link name="base"/>
<joint name="j1" type="revolute"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/>
<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<link name="a"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
<joint name="slide" type=")" + second_joint_type + R"("><parent link="a"/><child link="b"/><axis xyz="1 0 0"/>
<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<link name="b"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
</robot>)";
}

// The message of the InputError `f` throws (empty if it throws none); its line in `line`.
template <class F>
std::string refusal(F&& f, std::size_t* line = nullptr) {
  try {
    f();
  } catch (const InputError& e) {
    if (line) *line = e.line();
    return e.what();
  }
  return {};
}

TEST(ArmChain, RefusesAPrismaticJointNamingTheFileJointAndReason) {
  std::size_t line = 0;
  const std::string msg = refusal([] { RigidChain::from_urdf(two_link_urdf("prismatic"), "arm.urdf"); }, &line);
  EXPECT_EQ(line, 5u) << msg;  // the line of <joint name="slide" …>
  EXPECT_NE(msg.find("arm.urdf"), std::string::npos) << msg;
  EXPECT_NE(msg.find("field 'joint slide'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("type 'prismatic' is not supported"), std::string::npos) << msg;
  EXPECT_NE(msg.find("allowed: revolute, continuous, fixed"), std::string::npos) << msg;
  // the same chain with a revolute joint is accepted: the refusal is about the type
  EXPECT_EQ(RigidChain::from_urdf(two_link_urdf("revolute"), "arm.urdf").dof(), 2);
  EXPECT_EQ(RigidChain::from_urdf(two_link_urdf("continuous"), "arm.urdf").dof(), 2);
  EXPECT_NE(refusal([] { RigidChain::from_urdf(two_link_urdf("floating"), "f.urdf"); }).find("type 'floating'"),
            std::string::npos);
}

TEST(ArmChain, RefusesMalformedUrdfNamingTheFileAndUrdfdomsReason) {
  // a joint without a type: urdfdom's reason is passed on
  std::string bad = two_link_urdf("revolute");
  const std::string type = R"( type="revolute")";
  bad.replace(bad.find(type), type.size(), "");
  const std::string msg = refusal([&] { RigidChain::from_urdf(bad, "broken.urdf"); });
  EXPECT_NE(msg.find("broken.urdf"), std::string::npos) << msg;
  EXPECT_NE(msg.find("not a valid URDF"), std::string::npos) << msg;
  EXPECT_NE(msg.find("j1"), std::string::npos) << msg;  // urdfdom names the joint
  // not XML at all
  const std::string xml = refusal([] { RigidChain::from_urdf("<robot name='r'><link", "cut.urdf"); });
  EXPECT_NE(xml.find("cut.urdf"), std::string::npos) << xml;
}

TEST(ArmChain, RefusesABranchingTreeNamingTheLink) {
  std::string tree = two_link_urdf("revolute");
  tree.insert(tree.find("</robot>"), R"(<joint name="j3" type="revolute"><parent link="a"/><child link="c"/>
<axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
<link name="c"><inertial><mass value="1"/><inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>)");
  std::size_t line = 0;
  const std::string msg = refusal([&] { RigidChain::from_urdf(tree, "tree.urdf"); }, &line);
  EXPECT_EQ(line, 4u) << msg;  // the line of <link name="a">
  EXPECT_NE(msg.find("field 'link a'"), std::string::npos) << msg;
  EXPECT_NE(msg.find("branching"), std::string::npos) << msg;
}

TEST(ArmConfig, RefusesAnUnknownJointAndAMissingOneNamingTheKey) {
  const ArmText s = builtin_arm_text("scara-2");
  std::string toml(s.toml);
  toml.replace(toml.find(R"(name = "elbow")"), 14, R"(name = "wrist")");
  const std::string msg = refusal([&] { arm_from_text(s.urdf, "s.urdf", toml, "s.toml"); });
  EXPECT_NE(msg.find("s.toml"), std::string::npos) << msg;
  EXPECT_NE(msg.find("elbow"), std::string::npos) << msg;
  std::string bad_play(s.toml);
  bad_play.replace(bad_play.find("play_deg = 0.5"), 14, "play_deg = -1");
  const std::string play = refusal([&] { arm_from_text(s.urdf, "s.urdf", bad_play, "s.toml"); });
  EXPECT_NE(play.find("joint[0].play_deg"), std::string::npos) << play;
  EXPECT_NE(play.find("allowed: >= 0"), std::string::npos) << play;
}

}  // namespace
}  // namespace clearshape::arm
