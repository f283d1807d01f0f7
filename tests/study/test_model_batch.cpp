// study::simulate_drive_commands: a design loop's batch of simulations, neighbours on the
// fixed-step path stepped together. Each job must give what simulate_drive_command(…, true) gives
// alone, to the bit, and keep its own error: the fixed-step pairs, a CVODE job (a Hertz flank the
// fixed-step path does not cover), a job with an out-of-range start, and a pair in which one
// simulation diverges.
#include <cmath>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/units.hpp"
#include "clearshape/study/model.hpp"
#include "support/clearance_fixtures.hpp"

namespace clearshape::study {
namespace {

// The worn-coupling fit's model (1° of play, a linear dashpot flank, bearing Coulomb friction).
ClearanceModel worn_model(double stiffness) {
  ClearanceModel m = testing::thesis_position_clearance_model();
  m.play_rad = deg_to_rad(1.0);
  m.stiffness = stiffness;
  m.exponent = 1.0;
  m.damping = 0.13;
  m.coulomb_n_m = 0.01;
  return m;
}

UniformSeries step(double amplitude_deg, std::size_t n) {
  UniformSeries u{0.0, 1e-3, std::vector<double>(n, 0.0)};
  for (std::size_t k = 100; k < n; ++k) u.values[k] = amplitude_deg;
  return u;
}

std::string message_of(const std::exception_ptr& e) {
  try {
    std::rethrow_exception(e);
  } catch (const std::exception& x) {
    return x.what();
  }
}

TEST(SimulateDriveCommands, EachJobGivesItsOwnSimulationToTheBitAndKeepsItsError) {
  const ClearanceModel nominal = worn_model(45.0), stiffer = worn_model(60.0);
  ClearanceModel hertz = worn_model(45.0);
  hertz.exponent = 1.5;  // not on the fixed-step path: CVODE
  const UniformSeries u = step(20.0, 1501), v = step(-10.0, 1501);
  UniformSeries diverging = u;
  diverging.values[700] = std::numeric_limits<double>::quiet_NaN();
  const std::vector<DriveCommandJob> jobs = {
      {&nominal, &u, 1.5, -1.0}, {&stiffer, &v, 1.5, 0.5},    // a pair
      {&hertz, &u, 1.5, 0.0},                                  // CVODE, alone
      {&nominal, &u, 1.5, 2.0},                                // out of range: its error
      {&nominal, &u, 1.2, 1.0}, {&nominal, &v, 1.5, -0.5},     // lengths differ: alone each
      {&stiffer, &u, 1.5, 0.0}, {&nominal, &diverging, 1.5, 0.0}};  // a pair, one diverges
  const std::vector<DriveCommandOutcome> out = simulate_drive_commands(jobs);
  ASSERT_EQ(out.size(), jobs.size());
  int compared = 0, errors = 0;
  for (std::size_t i = 0; i < jobs.size(); ++i) {
    SCOPED_TRACE(i);
    const DriveCommandJob& j = jobs[i];
    try {
      const ModelResponse alone = simulate_drive_command(*j.model, *j.drive_command, j.duration_s, j.initial_play_fraction, true);
      ASSERT_FALSE(out[i].error) << message_of(out[i].error);
      EXPECT_EQ(out[i].response.link_angle_deg, alone.link_angle_deg);
      EXPECT_EQ(out[i].response.link_rate_deg_s, alone.link_rate_deg_s);
      EXPECT_EQ(out[i].response.motor_angle_deg, alone.motor_angle_deg);
      EXPECT_EQ(out[i].response.motor_rate_deg_s, alone.motor_rate_deg_s);
      EXPECT_EQ(out[i].response.drive_command, alone.drive_command);
      EXPECT_EQ(out[i].response.time_s, alone.time_s);
      ++compared;
    } catch (const std::exception& e) {
      ASSERT_TRUE(out[i].error) << "alone it throws: " << e.what();
      EXPECT_EQ(message_of(out[i].error), e.what());
      ++errors;
    }
  }
  EXPECT_EQ(compared, 6);
  EXPECT_EQ(errors, 2);  // the start 2.0 and the NaN command
  EXPECT_TRUE(out[3].error);
  EXPECT_TRUE(out[7].error);
  EXPECT_FALSE(out[6].error);  // the diverging job's partner kept its response
}

}  // namespace
}  // namespace clearshape::study
