// `clearshape rig calibrate`: excite the axis on the rig, record, recommend and export in one
// command (study/axis_calibration.hpp; docs/hardware.md "rig calibrate"). Parsing and printing
// only: the runs, the analysis and the design are the library's.
#include "cmd_rig_calibrate.hpp"

#include <cctype>
#include <cmath>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "clearshape/core/error.hpp"
#include "clearshape/export/export.hpp"
#include "clearshape/io/atomic_file.hpp"
#include "clearshape/io/interrupt.hpp"
#include "clearshape/io/json.hpp"
#include "clearshape/io/table.hpp"
#include "clearshape/study/axis_calibration.hpp"
#include "clearshape/study/recommend_report.hpp"
#include "command.hpp"
#include "option_checks.hpp"
#include "rig_serial_options.hpp"
#include "run_json.hpp"
#include "signal_options.hpp"

namespace cs = clearshape;
namespace rig = clearshape::rig;
using json = nlohmann::ordered_json;

namespace {

struct CalibrateState {
  cs::cli::SerialCliOptions serial;
  std::string excitation = "steps";
  std::string amplitudes;  // steps: "5,10,20" (position default)
  double start_s = 0.5;
  double rise_s = -1.0;    // < 0: one update period (position) or 0 (speed)
  double chirp_amplitude = 2.0;
  double f0_hz = 2.0;
  double f1_hz = 40.0;
  double sweep_s = 8.0;
  double duration_s = 0.0;  // 0: 3 s (steps) or sweep + 1 s (chirp)
  double from_s = 0.0;
  CLI::Option* from_option = nullptr;
  int modes = 1;
  double max_remaining = 0.2;
  double max_delay_s = 0.0;
  CLI::Option* delay_option = nullptr;
  double grid_hz = -1.0;    // < 0: the board's update rate in position mode, 0 in speed mode
  std::string format = "json";
  std::string output;
  std::string records;
  bool no_realtime = false;
  bool json = false;
};

std::vector<cs::signal::Signal> excitations(const CalibrateState& st, const rig::SerialRigOptions& o) {
  const bool position = o.mode == rig::CommandMode::position;
  if (st.excitation == "chirp") {
    cs::require_in_closed("--f0-hz", st.f0_hz, 0.01, 0.5 * o.sample_rate_hz);
    cs::require_in_closed("--f1-hz", st.f1_hz, st.f0_hz, 0.5 * o.sample_rate_hz);
    cs::require_in_closed("--sweep-s", st.sweep_s, 0.1, 600.0);
    if (!(std::isfinite(st.chirp_amplitude) && st.chirp_amplitude > 0.0)) {
      throw cs::InvalidArgument(fmt::format("--amplitude {:g}: allowed > 0 (deg or V)", st.chirp_amplitude));
    }
    return {cs::signal::Chirp{.amplitude = st.chirp_amplitude, .f0_hz = st.f0_hz, .f1_hz = st.f1_hz,
                              .sweep_s = st.sweep_s, .start_s = st.start_s}};
  }
  if (st.amplitudes.empty() && !position) {
    throw cs::InvalidArgument("--amplitudes: speed mode has no default steps; give the drive's voltages, e.g. 0.5,1,2");
  }
  const std::vector<double> a = st.amplitudes.empty() ? std::vector<double>{5.0, 10.0, 20.0}  // thesis Fig. 5.18, deg
                                                      : cs::cli::parse_levels(st.amplitudes, "--amplitudes");
  const double rise_s = st.rise_s >= 0.0 ? st.rise_s : (position ? 1.0 / o.update_rate_hz : 0.0);
  return cs::study::step_excitations(a, st.start_s, rise_s);
}

cs::study::AxisCalibrationRequest request(const CalibrateState& st, const rig::SerialRigOptions& o) {
  cs::study::AxisCalibrationRequest q;
  q.excitations = excitations(st, o);
  q.duration_s = st.duration_s > 0.0 ? st.duration_s : (st.excitation == "chirp" ? st.start_s + st.sweep_s + 1.0 : 3.0);
  cs::require_in_closed("--duration", q.duration_s, 0.1, 600.0);
  if (st.from_option->count() > 0) q.from_s = st.from_s;
  q.modes.max_modes = static_cast<std::size_t>(st.modes);
  cs::require_in_closed("--max-remaining", st.max_remaining, 0.0, 1.0);
  q.options.max_remaining = st.max_remaining;
  if (st.delay_option->count() > 0) {
    cs::require_positive("--max-delay-s", st.max_delay_s);
    q.options.max_delay_s = st.max_delay_s;
  }
  const double grid = st.grid_hz >= 0.0 ? st.grid_hz : (o.mode == rig::CommandMode::position ? o.update_rate_hz : 0.0);
  cs::require_in_closed("--grid-hz", grid, 0.0, o.sample_rate_hz);
  q.options.update_grid_hz = grid;
  q.modes.min_frequency_hz = q.options.min_frequency_hz;
  q.board.realtime_scheduling = !st.no_realtime;
  q.board.stop_flag = &cs::io::interrupt_requested();
  q.board.warn = [](const std::string& w) { fmt::print(stderr, "clearshape: warning: {}\n", w); };
  q.validate();
  return q;
}

// Each run's CSV and sidecar into --records (committed together; an incomplete run keeps its
// ".incomplete" name, as `rig run` writes it).
void write_records(const CalibrateState& st, const rig::SerialRig& board, const cs::study::AxisCalibrationRequest& q,
                   const std::vector<cs::study::AxisCalibrationRun>& runs) {
  if (st.records.empty()) return;
  std::filesystem::create_directories(st.records);
  cs::io::AtomicBatch batch;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto& run = runs[i];
    std::string stem = fmt::format("run-{}-{}", i + 1, run.label);
    for (char& ch : stem) ch = (std::isalnum(static_cast<unsigned char>(ch)) || ch == '-' || ch == '.') ? ch : '-';
    const std::string csv =
        rig::record_path_for((std::filesystem::path(st.records) / (stem + ".csv")).string(), run.outcome.complete());
    const rig::RecordColumns t = rig::record_columns(run.record, board.options().mode, true, false);
    auto doc = cs::io::make_document();
    doc["command"] = "rig calibrate";
    doc["csv"] = csv;
    doc["complete"] = run.outcome.complete();
    doc["degraded"] = run.outcome.degraded;
    doc["columns"] = t.names;
    doc["units"] = rig::record_units_json(board.options());
    doc["rig"] = {{"kind", "physical"}, {"board", rig::board_json(board)}};
    doc["configuration"] = rig::board_configuration_json(board.options());
    doc["configuration"]["duration_s"] = q.duration_s;
    doc["signal"] = {{"type", std::string(q.excitations[i].type())},
                     {"parameters", cs::cli::signal_parameters_json(q.excitations[i])}};
    doc["statistics"] = rig::run_statistics_json(run.outcome, run.record, board.options());
    doc["warnings"] = run.outcome.warnings;
    batch.add(csv, cs::io::format_csv(t.names, t.columns));
    batch.add(cs::cli::sidecar_path(csv), doc.dump(2) + "\n");
  }
  batch.commit();
  fmt::print(stderr, "clearshape rig calibrate: wrote {} run record(s) to {}\n", runs.size(), st.records);
}

void print_summary(const cs::study::AxisCalibration& c, const cs::exports::ShaperDesign& d, const CalibrateState& st) {
  for (std::size_t i = 0; i < c.spectra.size(); ++i) {
    fmt::print("run {:<2} {:<24} {} from {:.3f} s, {} Welch segments, resolution {:.3g} Hz\n", i + 1, c.spectra[i].source,
               c.spectra[i].column, c.window_start_s[i], c.spectra[i].segments, c.spectra[i].resolution_hz);
  }
  for (const auto& m : c.recommendation.modes) {
    fmt::print("mode    {:.4f} Hz ± {:.3g} (1σ), ζ {:.4f} ± {:.3g}\n", m.frequency_hz, m.frequency_std_hz, m.damping_ratio,
               m.damping_ratio_std);
  }
  const auto& r = c.recommendation;
  const auto& cand = r.candidates[*r.chosen];
  fmt::print("recommended {} at {:.4g} Hz: {:.2f} % of the vibration left in the worst case, {:.1f} ms delay\n", cand.name,
             fmt::join(cand.design_frequency_hz, "+"), 100.0 * cand.remaining_worst, 1000.0 * cand.duration_s);
  fmt::print("reason: {}\n", r.reason);
  fmt::print("shaper: {}\n", d.command);
  fmt::print("export: {} ({})\n", st.output, st.format);
}

void calibrate(const CalibrateState& st) {
  if (st.output.empty()) throw cs::InvalidArgument("rig calibrate: --output FILE is required (the exported shaper)");
  const cs::exports::Format format = cs::exports::format_from_string(st.format);
  if (st.modes < 1 || st.modes > 2) throw cs::InvalidArgument(fmt::format("--modes {}: allowed 1 or 2", st.modes));
  const rig::SerialRigOptions o = st.serial.build();
  const cs::study::AxisCalibrationRequest q = request(st, o);
  cs::io::DeferredInterrupts interrupts;  // a signal ends the run, STOP is sent, then the process ends
  rig::SerialRig board(o);
  cs::study::AxisCalibrationRequest qp = q;
  fmt::print(stderr, "clearshape rig calibrate: {} run(s) of {:g} s on {} ({} mode)\n", q.excitations.size(), q.duration_s,
             o.port, rig::to_string(o.mode));
  qp.board.progress = cs::cli::board_progress_printer(board, q.duration_s);
  const auto runs = cs::study::record_calibration_runs(board, qp);
  cs::cli::end_progress_line();
  write_records(st, board, q, runs);
  interrupts.end_process_if_interrupted();
  const cs::study::AxisCalibration c = cs::study::analyse_calibration(runs, q, board.sample_time_s());
  const cs::exports::ShaperDesign design = cs::study::recommended_design(c.recommendation, q.options);
  cs::exports::ExportOptions eo;
  eo.sample_time_s = board.sample_time_s();
  const cs::exports::ExportText text = cs::exports::export_shaper(design, format, eo);
  cs::io::write_text_atomic(st.output, text.text);
  for (const auto& note : text.notes) fmt::print(stderr, "clearshape rig calibrate: {}\n", note);
  if (!c.recommendation.warning.empty()) fmt::print(stderr, "clearshape: warning: {}\n", c.recommendation.warning);
  if (st.json) {
    cs::study::RecommendRequest rq;
    rq.options = q.options;
    rq.modes = q.modes;
    cs::study::RecommendReport report{c.spectra, c.estimation, c.recommendation, std::nullopt, std::nullopt};
    json doc = cs::study::recommend_document(rq, report);
    doc["command"] = "rig calibrate";
    doc["window_start_s"] = c.window_start_s;
    doc["export"] = {{"format", st.format}, {"path", st.output}};
    doc["records"] = st.records.empty() ? json(nullptr) : json(st.records);
    cs::cli::print_json(doc);
  } else {
    print_summary(c, design, st);
  }
}

}  // namespace

namespace clearshape::cli {

void add_rig_calibrate(CLI::App& rig_command) {
  auto st = std::make_shared<CalibrateState>();
  CLI::App* p = rig_command.add_subcommand(
      "calibrate", "Excite the axis, record, recommend a shaper and export it, in one command (Klipper's SHAPER_CALIBRATE)");
  st->serial.add_to(*p, true);
  p->add_option("--excitation", st->excitation, "steps (free decays after each step) or chirp (the forced response)")
      ->check(CLI::IsMember({"steps", "chirp"}))
      ->capture_default_str();
  p->add_option("--amplitudes", st->amplitudes, "Steps: comma-separated amplitudes, deg or V (position default: 5,10,20)");
  p->add_option("--start-s", st->start_s, "Where each excitation starts, s (the rest before it)")->capture_default_str();
  p->add_option("--rise-s", st->rise_s, "Steps: rise time, s (default: one update period in position mode, 0 in speed)");
  p->add_option("--amplitude", st->chirp_amplitude, "Chirp: amplitude, deg or V")->capture_default_str();
  p->add_option("--f0-hz", st->f0_hz, "Chirp: start frequency, Hz")->capture_default_str();
  p->add_option("--f1-hz", st->f1_hz, "Chirp: end frequency, Hz")->capture_default_str();
  p->add_option("--sweep-s", st->sweep_s, "Chirp: sweep length, s")->capture_default_str();
  p->add_option("--duration", st->duration_s, "Each run's length, s (default: 3 for steps, start + sweep + 1 for a chirp)");
  st->from_option = p->add_option("--from-s", st->from_s,
                                  "Analysis window start, s (default: the end of each step; a chirp's start)");
  p->add_option("--modes", st->modes, "Modes to look for: 1, or 2")->capture_default_str();
  p->add_option("--max-remaining", st->max_remaining, "Flag a pick leaving more than this fraction, [0, 1]")->capture_default_str();
  st->delay_option = p->add_option("--max-delay-s", st->max_delay_s, "Delay budget: longer candidates are not recommended, s");
  p->add_option("--grid-hz", st->grid_hz, "Design on the drive's update grid of this rate (default: the board's update rate "
                                          "in position mode; 0: none)");
  p->add_option("--export", st->format, "Export format: json, c-header, klipper or rrf")->capture_default_str();
  p->add_option("--output,-o", st->output, "The exported shaper's file")->required();
  p->add_option("--records", st->records, "Keep every run's CSV and sidecar in this folder (as `rig run` writes them)")
      ->check(cs::cli::output_folder());
  p->add_flag("--no-realtime", st->no_realtime, "Skip SCHED_FIFO and mlockall (run at normal priority)");
  p->add_flag("--json", st->json, "Print the result (the recommend document) as JSON");
  p->footer(
      "Examples:\n"
      "  clearshape rig calibrate --port /dev/ttyACM0 --records runs -o shaper.json\n"
      "  clearshape rig calibrate --port /dev/ttyACM0 --excitation chirp --amplitude 2 --f0-hz 2 --f1-hz 40 \\\n"
      "      --export c-header -o shaper.h");
  p->callback([st] { calibrate(*st); });
}

}  // namespace clearshape::cli
