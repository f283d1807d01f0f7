// The design model's position command path (study::simulate_command) is the rig's real-time
// pulse path: on the worn-coupling SimRig with no run-to-run variation (no start latency, unit
// gain), the model's motor angle follows the rig's encoder to within one count (0.03°) for a step,
// a low-jerk ramp and a shaped step. A path one sample tick off (it once lagged 33 whole samples
// instead of the 33.3 ms update) is 0.3–0.6° off on these moves.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/rig/worn_coupling.hpp"
#include "clearshape/shaping/apply.hpp"
#include "clearshape/signal/generators.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/study/model.hpp"
#include "clearshape/study/record.hpp"
#include "support/clearance_fixtures.hpp"

namespace cs = clearshape;
namespace st = clearshape::study;

namespace {

// The largest |model − rig| of the motor angle over the run (deg).
double motor_gap_deg(const cs::UniformSeries& command) {
  auto truth = cs::rig::worn_coupling_rig_truth();
  truth.variation = {};  // no start latency, unit drive gain, the nominal flank damping
  cs::rig::SimRigOptions o;
  o.mode = cs::rig::CommandMode::position;
  o.sample_rate_hz = 1.0 / command.sample_time_s;
  auto rig = cs::rig::make_sim_rig_with_truth(o, truth);
  st::RunRequest req;
  req.id = "path";
  req.command = command;
  req.record_s = static_cast<double>(command.values.size() - 1) * command.sample_time_s;
  const st::Record r = st::execute_run(*rig, req);
  st::ClearanceModel m = cs::testing::thesis_position_clearance_model();
  m.play_rad = truth.clearance_rad;
  m.stiffness = truth.position_contact.stiffness;
  m.exponent = 1.0;
  m.damping = truth.position_contact.damping;
  const st::ModelResponse model = st::simulate_command(m, command, req.record_s);
  double gap = 0.0;
  for (std::size_t k = 0; k < std::min(model.motor_angle_deg.size(), r.motor_angle_deg.size()); ++k) {
    gap = std::max(gap, std::abs(model.motor_angle_deg[k] - r.motor_angle_deg[k]));
  }
  return gap;
}

}  // namespace

TEST(ModelCommandPath, FollowsTheRigsRealTimePulsePath) {
  const double rate_hz = 1000.0;
  const auto step = cs::signal::sample(cs::signal::Step{20.0, 0.5}, rate_hz, 1.5);
  const auto ramp = cs::signal::sample(cs::signal::Step{56.0, 0.5, 0.1}, rate_hz, 1.5);
  const cs::shaping::Shaper zvd("zvd", {{0.0, 0.25}, {1.0 / 30.0, 0.5}, {2.0 / 30.0, 0.25}});
  const auto shaped = cs::shaping::shape_offline(zvd, cs::signal::sample(cs::signal::Step{10.0, 0.31}, rate_hz, 1.5), false);
  for (const auto& [name, command] : std::vector<std::pair<std::string, cs::UniformSeries>>{
           {"step 20 at 0.5 s", step}, {"56 over 0.1 s", ramp}, {"zvd step 10 at 0.31 s", shaped}}) {
    EXPECT_LT(motor_gap_deg(command), 0.031) << name;  // one encoder count: 360/12000
  }
}
