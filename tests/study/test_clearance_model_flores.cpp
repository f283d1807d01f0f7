// The Flores contact law of study::ClearanceModel against an independent path to the same
// physics: the large-play rig truth (rig::large_play_rig_truth, Flores e = 0.6, Hertz n = 1.5,
// bearing friction) run by rig::simulate_run, noise-free and without run-to-run variation. The
// model gets that truth's parameters and the drive command the truth recorded; its link must
// follow the truth's. And the dashpot default keeps its old response (the law is a choice, not a
// change), and the law round-trips through its names.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iostream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "clearshape/core/units.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/rig/large_play.hpp"
#include "clearshape/plant/command.hpp"
#include "clearshape/plant/simulation.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/signal/position_path.hpp"
#include "clearshape/study/model.hpp"
#include "support/clearance_fixtures.hpp"

namespace clearshape::study {
namespace {

constexpr double kTs = 1e-3;

// The large-play truth's joint as a ClearanceModel (Flores law), drive = the thesis's Eq. 4.2.
ClearanceModel model_of_truth(const rig::RigTruth& t) {
  return testing::flores_model_of_truth(t);
}

struct Comparison {
  double peak_deg_s = 0.0;
  double worst_deg_s = 0.0;
  double rms_deg_s = 0.0;
};

// A `amplitude_deg` step at 0.1 s through the truth's position path; the drive command that
// results drives (a) the truth's own plant (rig::plant_model, what `clearshape simulate --rig
// large-play` integrates, with its solver settings) and (b) the model. Both hold the command per
// 1 ms sample: `simulate` itself interpolates the pulse train linearly (rig/offline.hpp), a
// command-path difference this test is not about.
Comparison compare_step(double amplitude_deg, double duration_s, bool truth_solver) {
  const rig::RigTruth truth = rig::large_play_rig_truth();
  UniformSeries u;
  u.sample_time_s = kTs;
  u.values.assign(static_cast<std::size_t>(std::llround(duration_s / kTs)) + 1, 0.0);
  for (std::size_t k = 100; k < u.values.size(); ++k) u.values[k] = deg_to_rad(amplitude_deg);
  UniformSeries drive = signal::apply_position_path(u, truth.pulse_train, 0.0).commanded_rad;
  for (double& v : drive.values) v = rad_to_deg(v);  // the Eq. 4.2 drive maps deg → deg
  drive.start_s = 0.0;
  drive.sample_time_s = kTs;
  rig::RigTruth joint_only = truth;
  // The truth's link also has 1e-4 N·m·s/rad of drag to the ground (air, gyro cable), which the
  // model class does not carry (its viscous term acts on the relative rate): the joint is compared.
  joint_only.link.ground_viscous_n_m_s_per_rad = 0.0;
  const plant::PlantModel plant = rig::plant_model(joint_only, rig::CommandMode::position);
  plant::SimulationOptions options;
  options.duration_s = duration_s;
  options.output_rate_hz = 1.0 / kTs;
  if (truth_solver) options.solver = truth.solver;  // else the model's (SolverOptions' defaults)
  options.record_energy = false;
  options.initial.drive_state = Eigen::VectorXd::Zero(plant.drive.order());
  const plant::Simulation sim = plant::simulate(plant, plant::Command(drive, plant::Interpolation::zero_order_hold), options);
  const ModelResponse r = simulate_drive_command(model_of_truth(truth), drive, duration_s);
  Comparison c;
  const std::size_t n = std::min(r.link_rate_deg_s.size(), sim.link_rate_rad_s.size());
  EXPECT_GT(n, static_cast<std::size_t>(0.9 * duration_s / kTs));
  double ss = 0.0;
  for (std::size_t k = 0; k < n; ++k) {
    const double truth_deg_s = rad_to_deg(sim.link_rate_rad_s[k]);
    c.peak_deg_s = std::max(c.peak_deg_s, std::abs(truth_deg_s));
    c.worst_deg_s = std::max(c.worst_deg_s, std::abs(r.link_rate_deg_s[k] - truth_deg_s));
    ss += (r.link_rate_deg_s[k] - truth_deg_s) * (r.link_rate_deg_s[k] - truth_deg_s);
  }
  c.rms_deg_s = std::sqrt(ss / static_cast<double>(n));
  return c;
}

TEST(ClearanceModelFlores, FollowsTheLargePlayTruth) {
  for (double amplitude : {5.0, 20.0}) {
    SCOPED_TRACE(amplitude);
    const Comparison same = compare_step(amplitude, 1.0, false);
    const Comparison tight = compare_step(amplitude, 1.0, true);
    std::cout << amplitude << "°: peak " << same.peak_deg_s << " deg/s; model − truth (same solver) worst "
              << same.worst_deg_s << ", RMS " << same.rms_deg_s << "; (truth's tighter solver) worst " << tight.worst_deg_s
              << ", RMS " << tight.rms_deg_s << "\n";
    EXPECT_GT(same.peak_deg_s, 10.0 * amplitude);  // the link really moved and hit
    // Same equations, same CVODE settings: the same numbers up to floating-point reordering.
    EXPECT_LE(same.worst_deg_s, 1e-9 * same.peak_deg_s);
    // The truth's 10× tighter tolerances (rtol 1e-8): the model's own integration error, measured
    // 3e-5 (worst) and 1e-6 (RMS) of the peak; an impact misplaced by one output sample would be
    // of the order of the peak itself.
    EXPECT_LT(tight.worst_deg_s, 1e-4 * tight.peak_deg_s);
    EXPECT_LT(tight.rms_deg_s, 1e-5 * tight.peak_deg_s);
  }
}

TEST(ClearanceModelFlores, RestitutionChangesTheResponse) {
  // The same comparison with e = 0.8 in the model must fail by far: the law is really used.
  const rig::RigTruth truth = rig::large_play_rig_truth();
  ClearanceModel m = model_of_truth(truth);
  UniformSeries u;
  u.sample_time_s = kTs;
  u.values.assign(1001, 0.0);
  for (std::size_t k = 100; k < u.values.size(); ++k) u.values[k] = 20.0;
  const ModelResponse a = simulate_command(m, u, 1.0);
  m.restitution = 0.8;
  const ModelResponse b = simulate_command(m, u, 1.0);
  m.contact_law = ContactLawChoice::dashpot;  // D = 300 of the default
  const ModelResponse d = simulate_command(m, u, 1.0);
  double ab = 0.0, ad = 0.0;
  for (std::size_t k = 0; k < a.link_rate_deg_s.size(); ++k) {
    ab = std::max(ab, std::abs(a.link_rate_deg_s[k] - b.link_rate_deg_s[k]));
    ad = std::max(ad, std::abs(a.link_rate_deg_s[k] - d.link_rate_deg_s[k]));
  }
  EXPECT_GT(ab, 10.0);
  EXPECT_GT(ad, 10.0);
}

TEST(ClearanceModelFlores, NamesRoundTripAndUnknownIsRejected) {
  EXPECT_EQ(to_string(ContactLawChoice::dashpot), "dashpot");
  EXPECT_EQ(to_string(ContactLawChoice::flores), "flores");
  EXPECT_EQ(contact_law_from_string("flores"), ContactLawChoice::flores);
  EXPECT_EQ(contact_law_from_string("dashpot"), ContactLawChoice::dashpot);
  EXPECT_THROW(contact_law_from_string("hertz"), std::invalid_argument);
  EXPECT_EQ(ClearanceModel{}.contact_law, ContactLawChoice::dashpot);  // older callers: unchanged
}

TEST(ClearanceModelFlores, RestitutionOutsideItsRangeIsRejected) {
  ClearanceModel m = model_of_truth(rig::large_play_rig_truth());
  m.restitution = 1.5;
  UniformSeries u;
  u.sample_time_s = kTs;
  u.values.assign(101, 1.0);
  EXPECT_ANY_THROW(simulate_drive_command(m, u, 0.1));
}

}  // namespace
}  // namespace clearshape::study
