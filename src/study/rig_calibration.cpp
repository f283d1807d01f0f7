#include "clearshape/study/rig_calibration.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <mutex>
#include <ostream>
#include <thread>

#include <fmt/format.h>
#include <nlopt.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/encoder_speed.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/plant/drive.hpp"
#include "clearshape/rig/sim_rig.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/study/measures.hpp"
#include "clearshape/study/record.hpp"

namespace clearshape::study {

using json = nlohmann::ordered_json;

// ---------------------------------------------------------------------------------------------
// Step 1: the speed drive under the §3.3 chain.

namespace {

struct ChainData {
  double kp = 1.0;
  double sample_time_s = 1e-3;
  double duration_s = 2.0;
  std::vector<double> target;  // Eq. 4.2 unit-step response
  dsp::SosDesign filter = dsp::thesis_speed_filter(1e-3);
  int evaluations = 0;
};

lti::ProcessModel chain_drive(const ChainData& d, const double* x) {
  lti::ProcessParameters p;
  p.kp = d.kp;
  p.tz = x[0];
  p.zeta = std::exp(x[1]);
  p.tw = std::exp(x[2]);
  p.tp3 = std::exp(x[3]);
  return lti::ProcessModel("P3UZ", p);
}

double chain_rms(const ChainData& d, const lti::ProcessModel& drive) {
  const UniformSeries y = lti::step_response(drive, d.duration_s, d.sample_time_s);
  const std::vector<double> filtered = dsp::sosfilt(d.filter, y.values);  // causal chain (§3.3)
  const std::size_t n = std::min(filtered.size(), d.target.size());
  double ss = 0.0;
  for (std::size_t k = 0; k < n; ++k) ss += (filtered[k] - d.target[k]) * (filtered[k] - d.target[k]);
  return std::sqrt(ss / static_cast<double>(n));
}

double chain_objective(unsigned, const double* x, double*, void* data) {
  auto* d = static_cast<ChainData*>(data);
  ++d->evaluations;
  try {
    return chain_rms(*d, chain_drive(*d, x));
  } catch (const std::exception&) {
    return 1e30;
  }
}

}  // namespace

DriveChainFit fit_drive_under_chain(const lti::ProcessModel& identified, double duration_s,
                                    double sample_time_s, int max_evaluations) {
  ChainData d;
  d.kp = identified.parameters().kp;
  d.sample_time_s = sample_time_s;
  d.duration_s = duration_s;
  d.target = lti::step_response(identified, duration_s, sample_time_s).values;
  d.filter = dsp::thesis_speed_filter(sample_time_s);
  const auto& p = identified.parameters();
  // Start: the identified model itself (the filter only adds lag, so the drive is faster).
  std::vector<double> x{p.tz, std::log(p.zeta), std::log(p.tw), std::log(p.tp3)};
  std::vector<double> lo{-0.5, std::log(0.02), std::log(1e-3), std::log(1e-4)};
  std::vector<double> hi{0.5, std::log(1.5), std::log(1.0), std::log(1.0)};
  nlopt_opt opt = nlopt_create(NLOPT_LN_NELDERMEAD, 4);
  nlopt_set_lower_bounds(opt, lo.data());
  nlopt_set_upper_bounds(opt, hi.data());
  nlopt_set_min_objective(opt, chain_objective, &d);
  nlopt_set_maxeval(opt, max_evaluations);
  nlopt_set_xtol_rel(opt, 1e-8);
  std::vector<double> step{0.01, 0.2, 0.2, 0.2};
  nlopt_set_initial_step(opt, step.data());
  double value = 0.0;
  nlopt_optimize(opt, x.data(), &value);
  nlopt_destroy(opt);
  DriveChainFit fit;
  fit.drive = chain_drive(d, x.data());
  fit.rms_error_deg_s = chain_rms(d, fit.drive);
  fit.relative_error = fit.rms_error_deg_s / std::abs(d.kp);
  fit.evaluations = d.evaluations;
  return fit;
}

// ---------------------------------------------------------------------------------------------
// Unshaped trials on a SimRig with a given truth.

std::vector<TargetResidual> unshaped_residuals(const rig::RigTruth& truth, const Protocol& protocol,
                                               int trials, std::uint64_t seed, int threads) {
  struct Job {
    std::size_t target;
    int trial;
  };
  std::vector<TargetResidual> out;
  std::vector<const InputSpec*> inputs;
  for (const auto& table : protocol.rig_tests.tables) {
    for (const auto& col : table.columns) {
      if (col.key() != "none") continue;
      TargetResidual r;
      r.table = table.id;
      r.input = table.input;
      const MeanStd ms = mean_std(col.thesis.values);
      r.target_mean = col.thesis.mean.value_or(ms.mean);
      r.target_std = ms.std;
      out.push_back(r);
      inputs.push_back(&protocol.input(table.input));
    }
  }
  std::vector<Job> jobs;
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (int t = 0; t < trials; ++t) jobs.push_back({i, t});
  }
  std::vector<double> md(jobs.size(), 0.0);
  std::atomic<std::size_t> next{0};
  std::mutex error_mutex;
  std::exception_ptr error;
  auto worker = [&]() {
    for (std::size_t j = next.fetch_add(1); j < jobs.size(); j = next.fetch_add(1)) {
      try {
        const InputSpec& in = *inputs[jobs[j].target];
        RunRequest req;
        req.id = fmt::format("calibration/{}/r{:02d}", out[jobs[j].target].table, jobs[j].trial + 1);
        req.seed = run_seed(seed, req.id);
        req.command = signal::sample(in.signal, protocol.sample_rate_hz, protocol.record_s);
        req.record_s = protocol.record_s;
        rig::SimRigOptions o;
        o.mode = protocol.mode;
        o.sample_rate_hz = protocol.sample_rate_hz;
        o.seed = req.seed;
        auto sim = rig::make_sim_rig_with_truth(o, truth);
        const Record r = execute_run(*sim, req);
        md[j] = run_mean_deviation(r, protocol.measure, in).mean_deviation;
      } catch (...) {
        const std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < std::max(1, threads); ++t) pool.emplace_back(worker);
  worker();
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  for (std::size_t i = 0; i < out.size(); ++i) {
    std::vector<double> v;
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      if (jobs[j].target == i) v.push_back(md[j]);
    }
    const MeanStd ms = mean_std(v);
    out[i].ours_mean = ms.mean;
    out[i].ours_std = ms.std;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Step 2: position mode.

namespace {

struct PositionData {
  const Protocol* protocol = nullptr;
  rig::RigTruth base;
  RigCalibrationOptions options;
  int evaluations = 0;
  double best = std::numeric_limits<double>::infinity();
};

rig::RigTruth position_truth(const PositionData& d, const double* x) {
  rig::RigTruth t = d.base;
  t.clearance_rad = deg_to_rad(std::exp(x[0]));
  t.position_contact.stiffness = std::exp(x[1]);
  t.position_contact.damping = std::exp(x[2]);
  t.gyro.noise_density_dps_per_rthz = std::exp(x[3]);
  t.speed_contact = t.position_contact;  // one joint
  return t;
}

double score(const std::vector<TargetResidual>& res, double spread_weight) {
  double s = 0.0;
  for (const auto& r : res) {
    const double e = std::log(std::max(r.ours_mean, 1e-12) / r.target_mean);
    s += e * e;
    if (r.target_std > 0.0) {
      const double es = std::log(std::max(r.ours_std, 1e-12) / r.target_std);
      s += spread_weight * es * es;
    }
  }
  return s;
}

double position_objective(unsigned, const double* x, double*, void* data) {
  auto* d = static_cast<PositionData*>(data);
  ++d->evaluations;
  double s = 1e30;
  try {
    const auto res = unshaped_residuals(position_truth(*d, x), *d->protocol, d->options.trials,
                                        d->options.seed, d->options.threads);
    s = score(res, d->options.spread_weight);
  } catch (const std::exception&) {
  }
  if (s < d->best) d->best = s;
  if (d->options.progress) {
    *d->options.progress << fmt::format(
        "calibrate-rig: evaluation {:3d}: play {:.4f} deg, K {:.4g}, D {:.4g}, noise {:.4g} deg/s/rtHz -> {:.5f} (best {:.5f})\n",
        d->evaluations, std::exp(x[0]), std::exp(x[1]), std::exp(x[2]), std::exp(x[3]), s, d->best);
    d->options.progress->flush();
  }
  return s;
}

}  // namespace

RigCalibrationResult calibrate_rig(const Protocol& position, const Protocol& speed,
                                   const rig::RigTruth& start, const RigCalibrationOptions& options) {
  if (position.mode != rig::CommandMode::position || speed.mode != rig::CommandMode::speed) {
    throw InvalidArgument("calibrate_rig needs a position-mode and a speed-mode protocol, in that order");
  }
  RigCalibrationResult result;
  // 1. Speed drive under the filter chain.
  const auto& t = speed.identification.thesis;
  lti::ProcessParameters tp;
  tp.kp = t.kp;
  tp.tz = t.tz_s;
  tp.zeta = t.zeta;
  tp.tw = t.tw_s;
  tp.tp3 = t.tp3_s;
  result.speed_drive = fit_drive_under_chain(lti::ProcessModel("P3UZ", tp));
  if (options.progress) {
    const auto& p = result.speed_drive.drive.parameters();
    *options.progress << fmt::format(
        "calibrate-rig: speed drive under the 30 rad/s chain: Kp {:.4g}, Tz {:.4g} s, Zeta {:.4f}, Tw {:.4g} s, "
        "Tp3 {:.4g} s (RMS {:.3g} deg/s per V, {} evaluations)\n",
        p.kp, p.tz, p.zeta, p.tw, p.tp3, result.speed_drive.rms_error_deg_s, result.speed_drive.evaluations);
  }
  rig::RigTruth base = start;
  base.speed_drive = plant::DriveModel::from_process_model(plant::DriveMode::speed, result.speed_drive.drive);

  // 2. Position mode: play, K, D, gyro noise.
  PositionData d;
  d.protocol = &position;
  d.base = base;
  d.options = options;
  std::vector<double> x{std::log(rad_to_deg(start.clearance_rad)), std::log(start.position_contact.stiffness),
                        std::log(start.position_contact.damping),
                        std::log(start.gyro.noise_density_dps_per_rthz)};
  std::vector<double> lo{std::log(0.005), std::log(1.0), std::log(1e-4), std::log(1e-3)};
  std::vector<double> hi{std::log(2.0), std::log(1e5), std::log(1e2), std::log(0.1)};
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i], lo[i], hi[i]);
  nlopt_opt opt = nlopt_create(NLOPT_LN_BOBYQA, 4);
  nlopt_set_lower_bounds(opt, lo.data());
  nlopt_set_upper_bounds(opt, hi.data());
  nlopt_set_min_objective(opt, position_objective, &d);
  nlopt_set_maxeval(opt, options.max_evaluations);
  nlopt_set_xtol_rel(opt, 1e-3);
  std::vector<double> step{0.3, 0.3, 0.3, 0.3};
  nlopt_set_initial_step(opt, step.data());
  double value = 0.0;
  nlopt_optimize(opt, x.data(), &value);
  nlopt_destroy(opt);
  result.truth = position_truth(d, x.data());
  result.evaluations = d.evaluations;
  result.objective = value;

  // 3. Residuals of both modes with the calibrated truth (more trials than during the search).
  const int trials = std::max(options.trials, std::min(10, position.repetitions));
  result.residuals = unshaped_residuals(result.truth, position, trials, options.seed + 1, options.threads);
  const auto speed_res = unshaped_residuals(result.truth, speed, trials, options.seed + 1, options.threads);
  result.residuals.insert(result.residuals.end(), speed_res.begin(), speed_res.end());
  return result;
}

json RigCalibrationResult::to_json() const {
  json j;
  const auto& sd = speed_drive.drive.parameters();
  j["speed_drive"] = {{"structure", "P3UZ"}, {"kp", sd.kp}, {"tz_s", sd.tz}, {"zeta", sd.zeta},
                      {"tw_s", sd.tw}, {"tp3_s", sd.tp3},
                      {"chain_rms_error_deg_s_per_v", speed_drive.rms_error_deg_s},
                      {"evaluations", speed_drive.evaluations}};
  j["truth"] = {{"clearance_deg", rad_to_deg(truth.clearance_rad)},
                {"link_inertia_kg_m2", truth.link.inertia_kg_m2},
                {"contact_model", rig::to_string(truth.position_contact.model)},
                {"contact_stiffness", truth.position_contact.stiffness},
                {"contact_exponent", truth.position_contact.exponent},
                {"contact_damping_n_m_s_per_rad", truth.position_contact.damping},
                {"gyro_noise_density_dps_per_rthz", truth.gyro.noise_density_dps_per_rthz},
                {"gyro_low_pass_hz", plant::bandwidth_hz(truth.gyro.low_pass)}};
  json res = json::array();
  for (const auto& r : residuals) {
    res.push_back({{"table", r.table}, {"input", r.input}, {"target_mean", r.target_mean},
                   {"ours_mean", r.ours_mean}, {"relative_error", r.relative_error()},
                   {"target_std", r.target_std}, {"ours_std", r.ours_std}});
  }
  j["residuals"] = res;
  j["evaluations"] = evaluations;
  j["objective"] = objective;
  return j;
}

std::string truth_to_toml(const rig::RigTruth& t, const std::string& header_comment,
                          const lti::ProcessModel* speed_drive) {
  std::string s;
  for (std::size_t a = 0, b; a < header_comment.size(); a = b + 1) {
    b = header_comment.find('\n', a);
    if (b == std::string::npos) b = header_comment.size();
    s += "# " + header_comment.substr(a, b - a) + "\n";
  }
  const auto& c = t.position_contact;
  s += fmt::format("\n[joint]\nclearance_deg = {}\nfriction_viscous_n_m_s_per_rad = {}\nfriction_coulomb_n_m = {}\n",
                   rad_to_deg(t.clearance_rad), t.joint_friction.viscous, t.joint_friction.coulomb);
  s += fmt::format("\n[contact]\nmodel = \"{}\"\nstiffness = {}\nexponent = {}\ndamping = {}\nrestitution = {}\n",
                   rig::to_string(c.model),
                   c.stiffness, c.exponent, c.damping, c.restitution);
  s += fmt::format("\n[link]\ninertia_kg_m2 = {}\nmass_kg = {}\ncom_distance_m = {}\naxis_tilt_deg = {}\n"
                   "ground_viscous_n_m_s_per_rad = {}\n",
                   t.link.inertia_kg_m2, t.link.mass_kg, t.link.com_distance_m, rad_to_deg(t.link.axis_tilt_rad),
                   t.link.ground_viscous_n_m_s_per_rad);
  s += fmt::format("\n[gyroscope]\nnoise_density_dps_per_rthz = {}\nlow_pass_hz = {}\nbias_dps = {}\n",
                   t.gyro.noise_density_dps_per_rthz, plant::bandwidth_hz(t.gyro.low_pass), t.gyro.bias_dps);
  if (speed_drive) {
    const auto& p = speed_drive->parameters();
    s += fmt::format("\n[drive.speed]\nkp = {}\ntz_s = {}\nzeta = {}\ntw_s = {}\ntp3_s = {}\n", p.kp, p.tz, p.zeta,
                     p.tw, p.tp3);
  }
  return s;
}

}  // namespace clearshape::study
