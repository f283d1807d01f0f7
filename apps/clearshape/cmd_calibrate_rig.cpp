// `clearshape calibrate-rig`: calibrates the simulated rig's hidden truth to the thesis's
// measurements (docs/design.md §2; study/rig_calibration.hpp): the speed drive under the §3.3 filter
// chain, then the play, flank stiffness and damping and the gyro noise against the unshaped
// ("without is") means of Tables B.1–B.5, then the run-to-run variation against the mean Eq. 4.1
// errors of Tables 4.1–4.2 and the unshaped trials' spread (Tables 5.1, B.1–B.5). Writes
// rig-truth.toml (a `simulate --config` / `study --rig-config` file) and rig-calibration.json
// (parameters and residuals).
#include <filesystem>
#include <iostream>
#include <memory>
#include <string>

#include <fmt/format.h>

#include "clearshape/core/error.hpp"
#include "clearshape/core/units.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/rig/truth.hpp"
#include "clearshape/study/protocol.hpp"
#include "clearshape/study/rig_calibration.hpp"
#include "command.hpp"
#include "option_checks.hpp"

namespace clearshape::cli {
namespace {

struct CalibrateOptions {
  std::string position = "studies/thesis-position.toml";
  std::string speed = "studies/thesis-speed.toml";
  std::string out_dir = "out/calibrate-rig";
  int trials = 4;
  int max_evaluations = 80;
  int threads = 2;
  // The starting point of the search (found by exploring the thesis law with a linear flank).
  double play_deg = 0.05;
  double stiffness = 44.0;
  double exponent = 1.0;
  double damping = 0.12;
  double noise = 0.015;
  double spread_weight = 0.0;
  int variation_evaluations = 24;
  bool variation_only = false;
  bool json = false;
};

// Start: the uncalibrated physical prior with the search's starting joint; --variation-only
// keeps the built-in (calibrated) joint and fits the variation alone.
rig::RigTruth start_truth(const CalibrateOptions& o) {
  rig::RigTruth start = o.variation_only ? rig::thesis_rig_truth() : rig::uncalibrated_thesis_rig_prior();
  if (!o.variation_only) {
    start.clearance_rad = deg_to_rad(o.play_deg);
    start.position_contact.model = rig::ContactModel::thesis;
    start.position_contact.stiffness = o.stiffness;
    start.position_contact.exponent = o.exponent;
    start.position_contact.damping = o.damping;
    start.speed_contact = start.position_contact;
    start.gyro.noise_density_dps_per_rthz = o.noise;
  }
  start.validate();
  return start;
}

study::RigCalibrationOptions calibration_options(const CalibrateOptions& o) {
  study::RigCalibrationOptions options;
  options.trials = o.trials;
  options.max_evaluations = o.max_evaluations;
  options.threads = o.threads;
  options.spread_weight = o.spread_weight;
  options.variation_evaluations = o.variation_evaluations;
  options.fit_joint = !o.variation_only;
  options.progress = &std::cerr;
  return options;
}

// The rig-truth.toml header: how it was made, its targets and its residuals.
std::string toml_header(const CalibrateOptions& o, const study::RigCalibrationResult& result,
                        const std::filesystem::path& dir) {
  std::string header = fmt::format(
      "Simulated thesis rig, calibrated by `clearshape calibrate-rig{}` (joint: {} evaluations, objective {:.5f};\n"
      "variation: {} evaluations, objective {:.5f}).\n"
      "Targets: the unshaped means of Tables B.1-B.5 (position mode); the speed drive is fitted so that\n"
      "the thesis's Eq. 4.2 speed model is its response through the 30 rad/s Butterworth (thesis 3.3);\n"
      "the variation so that repeated runs give the mean Eq. 4.1 errors of Tables 4.1-4.2 and the\n"
      "unshaped trials' spread of Tables 5.1 and B.1-B.5.\n"
      "Use with: clearshape study <protocol> --rig-config {}\n"
      "Residuals of the unshaped Eq. 5.1 means, ours vs thesis:",
      o.variation_only ? " --variation-only" : "", result.evaluations, result.objective,
      result.variation.evaluations, result.variation.objective, (dir / "rig-truth.toml").string());
  for (const auto& r : result.residuals) {
    header += fmt::format("\n  {} {:.4f}/{:.4f} ({:+.1f} %), trials' sd {:.4f}/{:.4f}", r.table, r.ours_mean,
                          r.target_mean, 100.0 * r.relative_error(), r.ours_std, r.target_std);
  }
  if (result.variation.evaluations > 0) {
    header += "\nVariation targets, ours/thesis (other seeds than the search's):";
    for (const auto& r : result.variation.residuals) {
      if (r.quantity == "md_mean") continue;
      header += fmt::format("\n  {} {} {}: {:.3g}/{:.3g} (x{:.2f})", r.table, r.input, r.quantity, r.ours, r.target,
                            r.ours / r.target);
    }
  }
  return header;
}

void print_variation(const study::RigCalibrationResult& result) {
  const auto& v = result.variation.variation;
  fmt::print("\nVariation: drive gain sigma {:.3g} (position) / {:.3g} (speed), start latency <= {:.3g} s, "
             "D/A noise {:.3g} V, D/A offset sigma {:.3g} V, flank damping sigma {:.3g}\n",
             v.position_gain_rel_sigma, v.speed_gain_rel_sigma, v.start_latency_max_s, v.analog_noise_v,
             v.analog_offset_sigma_v, v.flank_damping_rel_sigma);
  fmt::print("{:<6} {:<18} {:<10} {:>10} {:>10} {:>8}\n", "table", "input", "quantity", "thesis", "ours", "ratio");
  for (const auto& r : result.variation.residuals) {
    fmt::print("{:<6} {:<18} {:<10} {:>10.4g} {:>10.4g} {:>8.2f}\n", r.table, r.input, r.quantity, r.target, r.ours,
               r.ours / r.target);
  }
}

void print_table(const study::RigCalibrationResult& result, const std::filesystem::path& dir) {
  const auto& sd = result.speed_drive.drive.parameters();
  fmt::print("Speed drive (truth) under the 30 rad/s chain: Kp {:.4g} (deg/s)/V, Tz {:.4g} s, Zeta {:.4f}, "
             "Tw {:.4g} s, Tp3 {:.4g} s; chain RMS {:.3g} deg/s per V\n",
             sd.kp, sd.tz, sd.zeta, sd.tw, sd.tp3, result.speed_drive.rms_error_deg_s);
  fmt::print("Joint: play {:.4f} deg, flank K {:.4g} N·m/rad^{:g}, D {:.4g} N·m·s/rad; gyro noise {:.4g} deg/s/rtHz\n",
             rad_to_deg(result.truth.clearance_rad), result.truth.position_contact.stiffness,
             result.truth.position_contact.exponent, result.truth.position_contact.damping,
             result.truth.gyro.noise_density_dps_per_rthz);
  fmt::print("\n{:<6} {:<18} {:>10} {:>10} {:>8} {:>10} {:>10}\n", "table", "input", "thesis", "ours", "error",
             "thesis sd", "ours sd");
  for (const auto& r : result.residuals) {
    fmt::print("{:<6} {:<18} {:>10.4f} {:>10.4f} {:>7.1f}% {:>10.4f} {:>10.4f}\n", r.table, r.input, r.target_mean,
               r.ours_mean, 100.0 * r.relative_error(), r.target_std, r.ours_std);
  }
  if (result.variation.evaluations > 0) print_variation(result);
  fmt::print("\nWritten: {} and {}\n", (dir / "rig-truth.toml").string(), (dir / "rig-calibration.json").string());
}

void run(const CalibrateOptions& o) {
  const study::Protocol position = study::load_protocol(o.position);
  const study::Protocol speed = study::load_protocol(o.speed);
  const rig::RigTruth start = start_truth(o);
  const study::RigCalibrationResult result = study::calibrate_rig(position, speed, start, calibration_options(o));

  const std::filesystem::path dir(o.out_dir);
  io::write_text_atomic(dir / "rig-truth.toml",
                        study::truth_to_toml(result.truth, toml_header(o, result, dir), &result.speed_drive.drive));
  auto doc = io::make_document();
  doc["calibration"] = result.to_json();
  doc["protocols"] = {o.position, o.speed};
  io::write_json(dir / "rig-calibration.json", doc);
  if (o.json) {
    print_json(doc);
  } else {
    print_table(result, dir);
  }
}

const bool calibrate_rig_registered = register_command(
    {"calibrate-rig", "Calibrate the simulated rig's truth to the thesis's unshaped measurements", 55,
     [](CLI::App& sub) {
       auto o = std::make_shared<CalibrateOptions>();
       sub.add_option("--position", o->position, "Position-mode protocol (targets B.1–B.5)")->capture_default_str();
       sub.add_option("--speed", o->speed, "Speed-mode protocol (Eq. 4.2 speed model, Table 5.1)")->capture_default_str();
       sub.add_option("--out", o->out_dir, "Output folder")->capture_default_str()->check(output_folder());
       sub.add_option("--trials", o->trials, "Unshaped trials per table and evaluation")
           ->capture_default_str()->check(CLI::Range(2, 100));
       sub.add_option("--max-evaluations", o->max_evaluations, "Evaluations of the search")
           ->capture_default_str()->check(CLI::Range(1, 10000));
       sub.add_option("--threads", o->threads, "Parallel trials")->capture_default_str()->check(CLI::Range(1, 256));
       sub.add_option("--start-play-deg", o->play_deg, "Start: total play (deg)")->capture_default_str();
       sub.add_option("--start-stiffness", o->stiffness, "Start: flank stiffness K (N·m/rad^n)")->capture_default_str();
       sub.add_option("--exponent", o->exponent, "Flank law exponent n (kept fixed)")->capture_default_str();
       sub.add_option("--start-damping", o->damping, "Start: flank damping D (N·m·s/rad)")->capture_default_str();
       sub.add_option("--start-noise", o->noise, "Start: gyro noise density (deg/s/rtHz)")->capture_default_str();
       sub.add_option("--spread-weight", o->spread_weight,
                      "Weight of the trials' spread in the joint's objective (0: means only; the spread is "
                      "fitted by the variation step)")
           ->capture_default_str()->check(CLI::Range(0.0, 10.0));
       sub.add_option("--variation-evaluations", o->variation_evaluations,
                      "Evaluations of the run-to-run variation fit (0: keep the start's variation)")
           ->capture_default_str()->check(CLI::Range(0, 10000));
       sub.add_flag("--variation-only", o->variation_only,
                    "Keep the built-in calibrated joint; fit only the run-to-run variation");
       sub.add_flag("--json", o->json, "Print the result as JSON");
       sub.callback([o] { run(*o); });
     }});

}  // namespace
}  // namespace clearshape::cli
