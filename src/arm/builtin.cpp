// The arms shipped with clearshape (docs/arm.md, "Built-in arms": where each number comes from).
// Both are two-link arms: links are aluminium tubes modelled as solid rods of radius r = 20 mm,
// about the centre of mass I_axial = m r²/2, I_transverse = m(3r² + L²)/12; the payload is a
// point mass at the tool. Drives are position-mode servos (P2U, Kp = 1 motor degree per command
// unit, ωn = 1/Tw = 2π·15 Hz, ζ = 0.8); the play is 0.5° per joint; the flank stiffness is that of
// small strain-wave/planetary gearboxes; Hunt–Crossley contact with steel-on-steel e = 0.5.
#include <fmt/format.h>

#include "clearshape/arm/arm.hpp"
#include "clearshape/core/error.hpp"

namespace clearshape::arm {

namespace {

struct Rod {
  double length_m, mass_kg;
};

struct TwoLinkArm {
  const char* name;
  const char* axis;       // both joint axes, in the base frame
  double shoulder_height_m;
  Rod upper, fore;
  double payload_kg;
  double gear[2];
  double stiffness_n_m_per_rad[2];
  const char* comment;
};

// scara-2: axes along z, gravity along −z: no joint torque from gravity, nothing loads the
// flanks of the play. vertical-2: axes along y, links in the x–z plane: gravity loads both plays
// except where its torque crosses zero (links vertical).
constexpr TwoLinkArm kArms[] = {
    {"scara-2", "0 0 1", 0.2, {0.25, 2.0}, {0.20, 1.0}, 0.5, {50.0, 30.0}, {3000.0, 1500.0},
     "horizontal two-link arm: gravity along the joint axes"},
    {"vertical-2", "0 1 0", 0.4, {0.30, 1.5}, {0.25, 0.8}, 0.3, {100.0, 50.0}, {5000.0, 2000.0},
     "two links in the vertical x-z plane"},
};

constexpr double kRodRadius_m = 0.02;

std::string inertial(double mass_kg, double com_x_m, double axial, double transverse) {
  return fmt::format(R"(    <inertial>
      <origin xyz="{} 0 0" rpy="0 0 0"/>
      <mass value="{}"/>
      <inertia ixx="{:.17g}" ixy="0" ixz="0" iyy="{:.17g}" iyz="0" izz="{:.17g}"/>
    </inertial>
)",
                     com_x_m, mass_kg, axial, transverse, transverse);
}

std::string rod_link(const char* name, const Rod& r) {
  const double r2 = kRodRadius_m * kRodRadius_m;
  const double axial = r.mass_kg * r2 / 2.0;                                   // m r²/2
  const double transverse = r.mass_kg * (3.0 * r2 + r.length_m * r.length_m) / 12.0;  // m(3r² + L²)/12
  return fmt::format("  <link name=\"{}\">\n{}  </link>\n", name, inertial(r.mass_kg, r.length_m / 2.0, axial, transverse));
}

std::string revolute(const char* name, const char* parent, const char* child, const std::string& xyz, const char* axis) {
  return fmt::format(R"(  <joint name="{}" type="revolute">
    <parent link="{}"/>
    <child link="{}"/>
    <origin xyz="{}" rpy="0 0 0"/>
    <axis xyz="{}"/>
    <limit lower="-2.6" upper="2.6" effort="40" velocity="6"/>
  </joint>
)",
                     name, parent, child, xyz, axis);
}

std::string urdf(const TwoLinkArm& a) {
  return fmt::format("<?xml version=\"1.0\"?>\n<!-- {}: {} (docs/arm.md) -->\n<robot name=\"{}\">\n  <link name=\"base_link\"/>\n",
                     a.name, a.comment, a.name) +
         revolute("shoulder", "base_link", "upper_arm", fmt::format("0 0 {}", a.shoulder_height_m), a.axis) +
         rod_link("upper_arm", a.upper) +
         revolute("elbow", "upper_arm", "forearm", fmt::format("{} 0 0", a.upper.length_m), a.axis) +
         rod_link("forearm", a.fore) +
         fmt::format(R"(  <joint name="tool_mount" type="fixed">
    <parent link="forearm"/>
    <child link="tool"/>
    <origin xyz="{} 0 0" rpy="0 0 0"/>
  </joint>
  <link name="tool">
{}  </link>
</robot>
)",
                     a.fore.length_m, inertial(a.payload_kg, 0.0, 1e-6, 1e-6));
}

std::string joint_toml(const char* name, double gear, double stiffness, double viscous, double coulomb) {
  return fmt::format(R"(
[[joint]]
name = "{}"
gear_ratio = {}
play_deg = 0.5
[joint.drive]
mode = "position"
model = "P2U"
kp = 1.0
tw = 0.0106103
zeta = 0.8
[joint.contact]
law = "hunt-crossley"
stiffness = {}
exponent = 1.0
restitution = 0.5
[joint.friction]
viscous_n_m_s_per_rad = {}
coulomb_n_m = {}
)",
                     name, gear, stiffness, viscous, coulomb);
}

std::string toml(const TwoLinkArm& a) {
  return fmt::format("# {}: drives, gears and play per joint (docs/arm.md)\n[arm]\nname = \"{}\"\n"
                     "gravity_m_s2 = [0.0, 0.0, -9.80665]\n",
                     a.name, a.name) +
         joint_toml("shoulder", a.gear[0], a.stiffness_n_m_per_rad[0], 0.02, 0.05) +
         joint_toml("elbow", a.gear[1], a.stiffness_n_m_per_rad[1], 0.01, 0.03);
}

}  // namespace

std::vector<std::string> builtin_arm_names() { return {"scara-2", "vertical-2"}; }

ArmText builtin_arm_text(std::string_view name) {
  for (const TwoLinkArm& a : kArms) {
    if (name == a.name) return {urdf(a), toml(a)};
  }
  throw InvalidArgument(fmt::format("arm '{}' is not a built-in arm; allowed: scara-2, vertical-2", name));
}

ArmModel builtin_arm(std::string_view name) {
  const ArmText text = builtin_arm_text(name);
  return arm_from_text(text.urdf, fmt::format("<builtin {}.urdf>", name), text.toml,
                       fmt::format("<builtin {}.toml>", name));
}

}  // namespace clearshape::arm
