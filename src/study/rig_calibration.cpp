#include "clearshape/study/rig_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <ostream>

#include <fmt/format.h>
#include <nlopt.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/parallel.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/dsp/encoder_speed.hpp"
#include "clearshape/dsp/sosfilt.hpp"
#include "clearshape/lti/simulate.hpp"
#include "clearshape/metrics/consistency.hpp"
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

namespace {

// One run of `input` on a fresh SimRig with `truth` (seed from `id`, as the study derives it).
struct RunJob {
  const InputSpec* input = nullptr;
  std::string id;
};

// Runs every job on `threads` threads; `use(j, record)` consumes job j's record (called from
// the worker threads, each j once; it must write only to j's own slot).
void run_jobs(const rig::RigTruth& truth, const Protocol& protocol, const std::vector<RunJob>& jobs,
              std::uint64_t seed, int threads, const std::function<void(std::size_t, const Record&)>& use) {
  parallel_for(jobs.size(), threads, [&](std::size_t j) {
    const InputSpec& in = *jobs[j].input;
    RunRequest req;
    req.id = jobs[j].id;
    req.seed = run_seed(seed, req.id);
    req.command = signal::sample(in.signal, protocol.sample_rate_hz, protocol.record_s);
    req.record_s = protocol.record_s;
    rig::SimRigOptions o;
    o.mode = protocol.mode;
    o.sample_rate_hz = protocol.sample_rate_hz;
    o.seed = req.seed;
    auto sim = rig::make_sim_rig_with_truth(o, truth);
    use(j, execute_run(*sim, req));
  });
}

}  // namespace

std::vector<TargetResidual> unshaped_residuals(const rig::RigTruth& truth, const Protocol& protocol,
                                               int trials, std::uint64_t seed, int threads) {
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
  std::vector<RunJob> jobs;
  std::vector<std::size_t> target_of;
  for (std::size_t i = 0; i < out.size(); ++i) {
    for (int t = 0; t < trials; ++t) {
      jobs.push_back({inputs[i], fmt::format("calibration/{}/r{:02d}", out[i].table, t + 1)});
      target_of.push_back(i);
    }
  }
  std::vector<double> md(jobs.size(), 0.0);
  run_jobs(truth, protocol, jobs, seed, threads, [&](std::size_t j, const Record& r) {
    md[j] = run_mean_deviation(r, protocol.measure, *jobs[j].input).mean_deviation;
  });
  for (std::size_t i = 0; i < out.size(); ++i) {
    std::vector<double> v;
    for (std::size_t j = 0; j < jobs.size(); ++j) {
      if (target_of[j] == i) v.push_back(md[j]);
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

// ---------------------------------------------------------------------------------------------
// Step 4: run-to-run variation.

double VariationResidual::log_error() const { return std::log(std::max(ours, 1e-300) / target); }

namespace {

// Eq. 4.1 mean error of each consistency input (Tables 4.1–4.2) over `repetitions` runs.
void consistency_residuals(const rig::RigTruth& truth, const Protocol& p, int repetitions, std::uint64_t seed,
                           int threads, std::vector<VariationResidual>& out) {
  const auto& cs = p.consistency;
  std::vector<RunJob> jobs;
  for (const auto& name : cs.inputs) {
    for (int r = 0; r < repetitions; ++r) jobs.push_back({&p.input(name), fmt::format("calibration/{}/{}/r{:02d}", cs.table, name, r + 1)});
  }
  const bool speed = p.mode == rig::CommandMode::speed;
  const bool zero_phase = p.identification.speed_chain == "zero-phase";
  std::vector<std::vector<double>> signals(jobs.size());
  run_jobs(truth, p, jobs, seed, threads, [&](std::size_t j, const Record& r) {
    signals[j] = speed ? motor_speed_deg_s(r, zero_phase) : r.motor_angle_deg;  // as stage_consistency
  });
  for (std::size_t i = 0; i < cs.inputs.size(); ++i) {
    const auto th = cs.thesis.find(cs.inputs[i]);
    if (th == cs.thesis.end()) continue;
    VariationResidual v;
    v.table = cs.table;
    v.input = cs.inputs[i];
    v.quantity = "eq41_mean";
    v.target = th->second.mean.value_or(mean_std(th->second.values).mean);
    const std::span<const std::vector<double>> runs(signals.data() + i * static_cast<std::size_t>(repetitions),
                                                    static_cast<std::size_t>(repetitions));
    v.ours = metrics::consistency_errors(runs).mean_error;
    out.push_back(v);
  }
}

}  // namespace

std::vector<VariationResidual> variation_residuals(const rig::RigTruth& truth, const Protocol& position,
                                                   const Protocol& speed, int repetitions,
                                                   std::uint64_t seed, int threads) {
  std::vector<VariationResidual> out;
  for (const Protocol* p : {&speed, &position}) {
    consistency_residuals(truth, *p, repetitions, seed, threads, out);
    for (const auto& r : unshaped_residuals(truth, *p, repetitions, seed, threads)) {
      out.push_back({r.table, r.input, "md_std", r.target_std, r.ours_std});
      out.push_back({r.table, r.input, "md_mean", r.target_mean, r.ours_mean});
    }
  }
  return out;
}

namespace {

struct VariationData {
  const Protocol* position = nullptr;
  const Protocol* speed = nullptr;
  rig::RigTruth base;
  VariationCalibrationOptions options;
  int evaluations = 0;
  double best = std::numeric_limits<double>::infinity();
};

// The fitted σ's, as logs (x) ↔ RunVariation.
constexpr int kVariationParameters = 6;
rig::RunVariation variation_from(const double* x) {
  rig::RunVariation v;
  v.position_gain_rel_sigma = std::exp(x[0]);
  v.speed_gain_rel_sigma = std::exp(x[1]);
  v.start_latency_max_s = std::exp(x[2]);
  v.analog_noise_v = std::exp(x[3]);
  v.analog_offset_sigma_v = std::exp(x[4]);
  v.flank_damping_rel_sigma = std::exp(x[5]);
  return v;
}

// Huber loss on the log errors (quadratic within a factor 2, linear beyond): a target no
// mechanism can reach (e.g. Table 4.2's double step) does not dominate the fit of the others.
double variation_score(const std::vector<VariationResidual>& res, double mean_weight) {
  const double k = std::log(2.0);
  double s = 0.0;
  for (const auto& r : res) {
    if (!(r.target > 0.0)) continue;
    const double e = std::abs(r.log_error());
    s += (r.quantity == "md_mean" ? mean_weight : 1.0) * (e <= k ? e * e : k * (2.0 * e - k));
  }
  return s;
}

double variation_objective(unsigned, const double* x, double*, void* data) {
  auto* d = static_cast<VariationData*>(data);
  ++d->evaluations;
  double s = 1e30;
  rig::RigTruth t = d->base;
  t.variation = variation_from(x);
  try {
    const auto res = variation_residuals(t, *d->position, *d->speed, d->options.repetitions, d->options.seed,
                                         d->options.threads);
    s = variation_score(res, d->options.mean_weight);
  } catch (const std::exception&) {
  }
  if (s < d->best) d->best = s;
  if (d->options.progress) {
    const auto& v = t.variation;
    *d->options.progress << fmt::format(
        "calibrate-rig: variation {:3d}: gain {:.3g}/{:.3g}, latency {:.3g} s, D/A noise {:.3g} V, offset {:.3g} V, "
        "flank D {:.3g} -> {:.5f} (best {:.5f})\n",
        d->evaluations, v.position_gain_rel_sigma, v.speed_gain_rel_sigma, v.start_latency_max_s, v.analog_noise_v,
        v.analog_offset_sigma_v, v.flank_damping_rel_sigma, s, d->best);
    d->options.progress->flush();
  }
  return s;
}

}  // namespace

VariationCalibrationResult calibrate_variation(const Protocol& position, const Protocol& speed,
                                               const rig::RigTruth& truth,
                                               const VariationCalibrationOptions& options) {
  if (position.mode != rig::CommandMode::position || speed.mode != rig::CommandMode::speed) {
    throw InvalidArgument("calibrate_variation needs a position-mode and a speed-mode protocol, in that order");
  }
  require_in_closed("repetitions", static_cast<double>(options.repetitions), 2.0, 100.0);
  VariationData d;
  d.position = &position;
  d.speed = &speed;
  d.base = truth;
  d.options = options;
  // Bounds (logs): relative gains 1e-6…0.05, latency 1e-7…0.9e-3 s (under one 1 kHz sample),
  // D/A 1e-6…0.05 V, flank 1e-3…1.
  const std::vector<double> lo{std::log(1e-6), std::log(1e-6), std::log(1e-7), std::log(1e-6), std::log(1e-6),
                               std::log(1e-3)};
  const std::vector<double> hi{std::log(0.05), std::log(0.05), std::log(0.9e-3), std::log(0.05), std::log(0.05),
                               std::log(1.0)};
  const auto& v0 = truth.variation;
  // Start: the truth's σ's where set, else an order-of-magnitude guess from Tables 4.1–4.2.
  const auto start = [](double value, double guess) { return std::log(value > 0.0 ? value : guess); };
  std::vector<double> x{start(v0.position_gain_rel_sigma, 1e-4), start(v0.speed_gain_rel_sigma, 2e-3),
                        start(v0.start_latency_max_s, 4e-4), start(v0.analog_noise_v, 1.2e-3),
                        start(v0.analog_offset_sigma_v, 1e-3), start(v0.flank_damping_rel_sigma, 0.15)};
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::clamp(x[i], lo[i], hi[i]);
  nlopt_opt opt = nlopt_create(NLOPT_LN_BOBYQA, kVariationParameters);
  nlopt_set_lower_bounds(opt, lo.data());
  nlopt_set_upper_bounds(opt, hi.data());
  nlopt_set_min_objective(opt, variation_objective, &d);
  nlopt_set_maxeval(opt, options.max_evaluations);
  nlopt_set_xtol_rel(opt, 1e-3);
  const std::vector<double> step(kVariationParameters, 0.7);  // a factor 2 per step
  nlopt_set_initial_step(opt, step.data());
  double value = 0.0;
  nlopt_optimize(opt, x.data(), &value);
  nlopt_destroy(opt);
  VariationCalibrationResult result;
  result.variation = variation_from(x.data());
  result.evaluations = d.evaluations;
  result.objective = value;
  rig::RigTruth t = truth;
  t.variation = result.variation;
  // Residuals on other seeds than the search's (a check against fitting the draws).
  result.residuals =
      variation_residuals(t, position, speed, options.final_repetitions, options.seed + 1, options.threads);
  return result;
}

json VariationCalibrationResult::to_json() const {
  json j;
  j["variation"] = {{"position_gain_rel_sigma", variation.position_gain_rel_sigma},
                    {"speed_gain_rel_sigma", variation.speed_gain_rel_sigma},
                    {"start_latency_max_s", variation.start_latency_max_s},
                    {"analog_noise_v", variation.analog_noise_v},
                    {"analog_offset_sigma_v", variation.analog_offset_sigma_v},
                    {"flank_damping_rel_sigma", variation.flank_damping_rel_sigma}};
  json res = json::array();
  for (const auto& r : residuals) {
    res.push_back({{"table", r.table}, {"input", r.input}, {"quantity", r.quantity}, {"target", r.target},
                   {"ours", r.ours}, {"ratio", r.target > 0.0 ? r.ours / r.target : 0.0}});
  }
  j["residuals"] = res;
  j["evaluations"] = evaluations;
  j["objective"] = objective;
  return j;
}

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
  if (options.fit_joint) {
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
  } else {
    result.truth = base;  // the start's joint, kept
  }

  // 4. Run-to-run variation with the joint fixed.
  if (options.variation_evaluations > 0) {
    VariationCalibrationOptions vo;
    vo.final_repetitions = std::max(2, std::min(10, position.repetitions));
    vo.repetitions = std::min(vo.repetitions, vo.final_repetitions);
    vo.max_evaluations = options.variation_evaluations;
    vo.seed = options.seed;
    vo.threads = options.threads;
    vo.progress = options.progress;
    result.variation = calibrate_variation(position, speed, result.truth, vo);
    result.truth.variation = result.variation.variation;
  }

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
  if (variation.evaluations > 0) j["variation"] = variation.to_json();
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
  const auto& v = t.variation;
  s += fmt::format("\n[variation]\nposition_gain_rel_sigma = {}\nspeed_gain_rel_sigma = {}\nstart_latency_max_s = {}\n"
                   "analog_noise_v = {}\nanalog_offset_sigma_v = {}\nflank_damping_rel_sigma = {}\n",
                   v.position_gain_rel_sigma, v.speed_gain_rel_sigma, v.start_latency_max_s, v.analog_noise_v,
                   v.analog_offset_sigma_v, v.flank_damping_rel_sigma);
  if (speed_drive) {
    const auto& p = speed_drive->parameters();
    s += fmt::format("\n[drive.speed]\nkp = {}\ntz_s = {}\nzeta = {}\ntw_s = {}\ntp3_s = {}\n", p.kp, p.tz, p.zeta,
                     p.tw, p.tp3);
  }
  return s;
}

}  // namespace clearshape::study
