// The per-run joint fit (study/model.hpp fit_clearance_runs, issue 19) on records of the built-in
// worn-coupling truth (rig/worn_coupling.hpp) taken through the SimRig's sensors — the 30 Hz
// pulse-train command path, the encoder, the ITG-3205 gyroscope with its noise and DLPF, the
// thesis rig's run-to-run variation and a link that starts at a random place in the play each
// run. Each run keeps its own start place (a nuisance parameter); nothing is averaged.
// Checked at 0.5, 1 and 2° of play (six 2 s runs of a 5° step each): play and K within ±10 %, the
// Coulomb torque within ±25 % of the truth, each truth within 2σ of its fit, the n-free
// alternative not significantly better (χ²₁ < 3.84), and the fixed-step optimum confirmed by
// CVODE (RMS within 5 %).
#include <chrono>
#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/lti/process_model.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/rig/worn_coupling.hpp"
#include "clearshape/study/model.hpp"
#include "clearshape/study/record.hpp"

namespace clearshape::study {
namespace {

constexpr double kTs = 1e-3;
constexpr double kRecordS = 2.0;
constexpr int kRuns = 6;

// A 5° step at 0.5 s ramped over one 30 Hz pulse update (the studies' step-5 input).
UniformSeries step_command() {
  UniformSeries u;
  u.sample_time_s = kTs;
  u.values.assign(static_cast<std::size_t>(kRecordS / kTs) + 1, 0.0);
  for (std::size_t k = 500; k < u.values.size(); ++k) {
    u.values[k] = 5.0 * std::min(1.0, (static_cast<double>(k) - 500.0) / 33.3);
  }
  return u;
}

// kRuns seeded runs of the worn coupling with `play_deg` through the rig's sensors.
std::vector<ClearanceRunRecord> records(double play_deg) {
  const rig::RigTruth truth = rig::worn_coupling_rig_truth(rig::WornCoupling{play_deg});
  std::vector<ClearanceRunRecord> out;
  for (int r = 1; r <= kRuns; ++r) {
    rig::SimRigOptions o;
    o.seed = run_seed(2026, fmt::format("worn-{}/r{}", play_deg, r));
    auto sim = rig::make_sim_rig_with_truth(o, truth);
    RunRequest req;
    req.id = fmt::format("r{:02}", r);
    req.command = step_command();
    req.record_s = kRecordS;
    const Record rec = execute_run(*sim, req);
    ClearanceRunRecord run;
    run.id = req.id;
    run.drive_command.sample_time_s = kTs;
    run.drive_command.values = rec.command_applied;
    run.link_rate_deg_s = rec.link_rate_deg_s;
    out.push_back(std::move(run));
  }
  return out;
}

ClearanceRunsFitProblem problem(double play_deg) {
  ClearanceRunsFitProblem p;
  p.start.drive = lti::thesis_position_mode_model();  // the thesis's position drive (Eq. 4.2, §4.2)
  p.start.link_inertia_kg_m2 = 5e-3;
  p.start.exponent = 1.0;
  p.start.play_rad = deg_to_rad(0.1);  // the protocols' start: far from every truth
  p.start.stiffness = 100.0;
  p.start.damping = 0.3;
  p.runs = records(play_deg);
  p.duration_s = kRecordS;
  p.sensor_low_pass_grid_hz = {0.0, 98.0, 42.0, 20.0};
  return p;
}

const ClearanceParameter& param(const ClearanceRunsFitResult& r, const std::string& name) {
  for (const auto& q : r.parameters) {
    if (q.name == name) return q;
  }
  throw std::runtime_error("no parameter " + name);
}

void check_play(double play_deg) {
  const auto t0 = std::chrono::steady_clock::now();
  const ClearanceRunsFitProblem p = problem(play_deg);
  const auto t1 = std::chrono::steady_clock::now();
  const ClearanceRunsFitResult r = fit_clearance_runs(p);
  const auto t2 = std::chrono::steady_clock::now();
  const rig::RigTruth truth = rig::worn_coupling_rig_truth(rig::WornCoupling{play_deg});
  const double k_true = truth.position_contact.stiffness, c_true = truth.joint_friction.coulomb;
  const auto& play = param(r, "play");
  const auto& k = param(r, "stiffness");
  const auto& c = param(r, "coulomb");
  std::cout << fmt::format(
      "play {}°: fitted {:.4f}° ± {:.1f} % ({:+.1f} %), K {:.3f} ± {:.1f} % ({:+.1f} %), D {:.4f} ± {:.1f} %, "
      "c {:.4g} ± {:.1f} % ({:+.1f} %), b {:.3g} ± {:.0f} %; RMS {:.3f} deg/s (CVODE {:.3f}), DLPF {} Hz; "
      "n-free: n {:.3f} ± {:.3f}, χ² {:.2f}; {} iterations ({}), {} simulations; records {:.1f} s, fit {:.1f} s\n",
      play_deg, rad_to_deg(play.value), 100 * play.std_error, 100 * (rad_to_deg(play.value) / play_deg - 1),
      k.value, 100 * k.std_error, 100 * (k.value / k_true - 1), r.model.damping, 100 * param(r, "damping").std_error,
      c.value, 100 * c.std_error, 100 * (c.value / c_true - 1), r.model.viscous_n_m_s_per_rad,
      100 * param(r, "viscous").std_error, r.rms_error_deg_s, r.check_rms_error_deg_s, r.sensor_low_pass_hz,
      r.exponent_free_value, r.exponent_free_std, r.exponent_chi2, r.iterations, r.termination, r.simulations,
      std::chrono::duration<double>(t1 - t0).count(), std::chrono::duration<double>(t2 - t1).count());
  for (std::size_t i = 0; i < r.start_fraction.size(); ++i) {
    std::cout << fmt::format("  {} start {:+.3f} ± {:.3f}, RMS {:.3f}\n", r.run_ids[i], r.start_fraction[i],
                             r.start_fraction_std[i], r.run_rms_error_deg_s[i]);
  }
  const double play_rel = rad_to_deg(play.value) / play_deg - 1.0;
  EXPECT_LT(std::abs(play_rel), 0.10) << "play";
  EXPECT_LT(std::abs(k.value / k_true - 1.0), 0.10) << "K";
  EXPECT_LT(std::abs(c.value / c_true - 1.0), 0.25) << "Coulomb";
  // The 1σ covers the truth: within 2σ (log σ for play and K, relative for c). Measured: within
  // 0.3σ at every play. Before the fixed-step path located contact onsets and the fit refined from
  // the scan's three best points, 2° read 3.0σ (play) and 2.8σ (K), errors of 0.2–0.3 %.
  EXPECT_LT(std::abs(std::log(rad_to_deg(play.value) / play_deg)), 2.0 * play.std_error) << "play σ";
  EXPECT_LT(std::abs(std::log(k.value / k_true)), 2.0 * k.std_error) << "K σ";
  EXPECT_LT(std::abs(c.value / c_true - 1.0), 2.0 * c.std_error) << "Coulomb σ";
  EXPECT_FALSE(r.exponent_free_better) << "the n-free fit is significantly better: χ² " << r.exponent_chi2;
  EXPECT_LT(std::abs(r.check_rms_error_deg_s - r.rms_error_deg_s), 0.05 * r.rms_error_deg_s) << "CVODE check";
  const ClearanceModelSigma s = r.sigma();
  EXPECT_GT(s.play_rel_sigma, 0.0);
  EXPECT_GT(s.stiffness_rel_sigma, 0.0);
  EXPECT_GT(s.coulomb_rel_sigma, 0.0);
}

TEST(ClearanceFitRuns, FindsTheWornCouplingAtHalfADegree) { check_play(0.5); }
TEST(ClearanceFitRuns, FindsTheWornCouplingAtOneDegree) { check_play(1.0); }
TEST(ClearanceFitRuns, FindsTheWornCouplingAtTwoDegrees) { check_play(2.0); }

TEST(ClearanceFitRuns, RejectsAnIllPosedProblem) {
  ClearanceRunsFitProblem p;
  p.start.play_rad = deg_to_rad(0.1);
  try {
    (void)fit_clearance_runs(p);
    FAIL() << "no runs accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("runs"), std::string::npos) << e.what();
  }
  p.runs.resize(1);
  p.runs[0].drive_command.sample_time_s = kTs;
  p.runs[0].drive_command.values.assign(100, 0.0);
  p.runs[0].link_rate_deg_s.assign(100, 0.0);
  try {
    (void)fit_clearance_runs(p);
    FAIL() << "a record shorter than duration_s accepted";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("runs[0] samples"), std::string::npos) << e.what();
  }
  p.free = {"exponent"};
  p.duration_s = 0.05;
  try {
    (void)fit_clearance_runs(p);
    FAIL() << "the exponent accepted as a shared parameter";
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("exponent"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace clearshape::study
