// The clearance fit with the Flores restitution law (study/model.hpp, contact_law = flores: the
// restitution e fitted in place of the dashpot D). The record comes from the large-play rig
// truth's joint (rig::large_play_rig_truth: Hertz pin n = 1.5, K from Eq. 2.5–2.6, Flores
// e = 0.6, 1° play, bearing Coulomb 2e-3 N·m and viscous 1e-4 N·m·s/rad) as a ClearanceModel
// under a 5° step (the move whose free flight across the play carries the friction), noise-free
// and with the truth gyroscope's noise. Checked: the fit recovers e, the play and c (K only
// weakly: see below); the exponent is held at the truth's 1.5 (a Hertz pin, known from contact
// mechanics), as in test_clearance_fit_friction.cpp.
#include <cmath>
#include <iostream>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "clearshape/core/units.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/rig/large_play.hpp"
#include "clearshape/study/model.hpp"
#include "support/clearance_fixtures.hpp"

namespace clearshape::study {
namespace {

constexpr double kTs = 1e-3;
constexpr double kDuration = 1.5;

// The large-play truth's joint as a ClearanceModel (Flores law; test_clearance_model_flores.cpp
// shows it integrates to the same numbers as the truth's own plant under the same command).
ClearanceModel truth_model() {
  return testing::flores_model_of_truth(rig::large_play_rig_truth());
}

// A 5° step at 0.2 s ramped over one 30 Hz update (the studies' steps), through the position
// path; the record is the link rate plus the truth gyroscope's white noise (seeded), σ = ρ·√(f_s/2).
ClearanceFitProblem problem(bool noise) {
  UniformSeries u;
  u.sample_time_s = kTs;
  u.values.assign(static_cast<std::size_t>(kDuration / kTs) + 1, 0.0);
  for (std::size_t k = 200; k < u.values.size(); ++k) u.values[k] = 5.0 * std::min(1.0, (static_cast<double>(k) - 200.0) / 33.3);
  const ModelResponse r = simulate_command(truth_model(), u, kDuration);
  ClearanceFitProblem p;
  p.drive_command.sample_time_s = kTs;
  p.drive_command.values = r.drive_command;  // deg: what the drive received
  p.duration_s = kDuration;
  p.measured_link_rate_deg_s = r.link_rate_deg_s;
  if (noise) {
    const double sigma = rig::large_play_rig_truth().gyro.noise_density_dps_per_rthz * std::sqrt(0.5 / kTs);
    std::mt19937_64 rng(2026);
    std::normal_distribution<double> normal(0.0, sigma);
    for (double& v : p.measured_link_rate_deg_s) v += normal(rng);
  }
  p.start = truth_model();  // drive, inertia, law; the fitted values start far off
  p.start.restitution = 0.9;
  p.start.stiffness = 0.1 * p.start.stiffness;  // a decade low
  p.start.play_rad = deg_to_rad(0.5);           // half the truth's
  p.start.coulomb_n_m = 0.0;
  p.start.viscous_n_m_s_per_rad = 0.0;
  p.free = {"stiffness", "restitution", "play", "coulomb", "viscous"};
  p.max_evaluations = 400;
  return p;
}

struct Errors {
  double e, k, play, coulomb;
};

Errors errors_of(const ClearanceFitResult& r) {
  const rig::RigTruth t = rig::large_play_rig_truth();
  const ClearanceModel& m = r.model;
  std::cout << "flores fit: e " << m.restitution << ", K " << m.stiffness << " (truth " << t.position_contact.stiffness
            << "), play " << rad_to_deg(m.play_rad) << " deg, c " << m.coulomb_n_m << " N·m, b " << m.viscous_n_m_s_per_rad
            << ", RMS " << r.rms_error_deg_s << " deg/s, 1σ:";
  for (const auto& q : r.parameters) {
    if (q.free) std::cout << " " << q.name << " " << q.std_error << (q.identifiable ? "" : " (not identifiable)");
  }
  std::cout << ", start RMS " << r.start_rms_error_deg_s << " deg/s, " << r.evaluations << " evaluations, " << r.termination << "\n";
  return {m.restitution / 0.6 - 1.0, m.stiffness / t.position_contact.stiffness - 1.0,
          rad_to_deg(m.play_rad) / 1.0 - 1.0, m.coulomb_n_m / 2e-3 - 1.0};
}

// The contact of a K ≈ 1e6 N·m/rad^1.5 pin lasts about 2 ms per impact, two gyro samples: K is
// seen only through those few samples and trades against the play (a stiffer flank needs a
// slightly larger play for the same travel), so the search ends with K a factor 2–4 off while e,
// the play and c — which set the rebound heights, the free-flight times and their decay over the
// whole record — come out close. Measured (noise-free / with noise): e +0.3 % / −0.8 %, play
// +3.6 % / −4.8 %, c +4.8 % / −6.5 %, K ×3.8 / ×0.37. Tolerances: e 3 %, play 6 % and c 10 %
// noise-free; e 5 %, play 8 %, c 15 % with noise; K only within a factor 5 (weakly determined).
TEST(ClearanceFitFlores, RecoversTheLargePlayJointNoiseFree) {
  const ClearanceFitResult r = fit_clearance(problem(false));
  const Errors e = errors_of(r);
  EXPECT_LT(std::abs(e.e), 0.03);
  EXPECT_LT(std::abs(e.play), 0.06);
  EXPECT_LT(std::abs(e.coulomb), 0.10);
  EXPECT_LT(std::abs(std::log(1.0 + e.k)), std::log(5.0));
  bool named = false;
  for (const auto& q : r.parameters) {
    if (q.name == "restitution") {
      named = true;
      EXPECT_TRUE(q.free);
      EXPECT_EQ(clearance_parameter_unit(q.name), "1");
    }
    EXPECT_NE(q.name, "damping");  // the Flores law has no D
  }
  EXPECT_TRUE(named);
}

// With the truth gyroscope's white noise (0.03 deg/s/√Hz over 500 Hz ≈ 0.67 deg/s RMS).
TEST(ClearanceFitFlores, RecoversTheLargePlayJointWithGyroNoise) {
  const Errors e = errors_of(fit_clearance(problem(true)));
  EXPECT_LT(std::abs(e.e), 0.05);
  EXPECT_LT(std::abs(e.play), 0.08);
  EXPECT_LT(std::abs(e.coulomb), 0.15);
  EXPECT_LT(std::abs(std::log(1.0 + e.k)), std::log(5.0));
}

TEST(ClearanceFitFlores, DampingIsNotANameOfTheDashpotFitsRestitution) {
  ClearanceFitProblem p = problem(false);
  p.start.contact_law = ContactLawChoice::dashpot;
  p.start.damping = 1.0;
  p.free = {"restitution"};  // the dashpot law has no e
  EXPECT_THROW(fit_clearance(p), std::invalid_argument);
  p.start.contact_law = ContactLawChoice::flores;
  p.start.restitution = 1.5;  // outside (0, 1]
  p.free = {"stiffness"};
  EXPECT_THROW(fit_clearance(p), std::invalid_argument);
}

}  // namespace
}  // namespace clearshape::study
