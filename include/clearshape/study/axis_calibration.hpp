#pragma once
// Calibrating an axis on the rig in one step — what Klipper's SHAPER_CALIBRATE does for a
// printer, for a servo joint with the thesis's sensors (docs/hardware.md "rig calibrate"):
//   1. excite: each excitation (the protocol's steps, or a chirp) is one run on the board
//      (rig/board_run.hpp), the link's gyroscope recorded;
//   2. analyse: the gyro rate in each run's analysis window becomes a Welch spectrum
//      (advise/spectrum_input.hpp), the modes are estimated over all of them and the candidates
//      ranked by their worst case (advise/recommend.hpp) — the same path as `clearshape recommend`
//      on the saved records;
//   3. design: the recommended candidate as an exports::ShaperDesign, ready for export_shaper.
// A run that is not complete stops the calibration; no spectrum ever comes from a degraded record.
//
//   rig::SerialRig board(serial_options);
//   study::AxisCalibrationRequest request;  request.excitations = study::step_excitations({5, 10, 20}, 0.5, 1 / 30.);
//   const auto runs = study::record_calibration_runs(board, request);   // save runs[i].record
//   const study::AxisCalibration c = study::analyse_calibration(runs, request, board.sample_time_s());
//   const exports::ShaperDesign d = study::recommended_design(c.recommendation, request.options);
#include <optional>
#include <string>
#include <vector>

#include "clearshape/advise/mode_estimate.hpp"
#include "clearshape/advise/recommend.hpp"
#include "clearshape/advise/spectrum_input.hpp"
#include "clearshape/export/export.hpp"
#include "clearshape/rig/board_run.hpp"
#include "clearshape/rig/serial_rig.hpp"
#include "clearshape/signal/signal.hpp"

namespace clearshape::study {

struct AxisCalibrationRequest {
  std::vector<signal::Signal> excitations;  ///< one board run each, at least one
  double duration_s = 3.0;                  ///< each run's length, (0, 600] s
  /// The analysis window starts here (s from the run's start); none: where the run's command
  /// stops changing (a step's end: its free decay), or, for a command that still changes in the
  /// last quarter of the run (a chirp), where it starts changing (the forced response).
  std::optional<double> from_s;
  double segment_s = 0.0;                   ///< Welch segment, s (0: advise's automatic choice)
  advise::ModeEstimateOptions modes;
  advise::RecommendOptions options;
  /// Realtime scheduling, the stop flag, warnings and progress for every run (its command is
  /// set per run).
  rig::BoardRunOptions board;
  /// Throws InvalidArgument naming the field and its range.
  void validate() const;
};

/// The steps of `amplitudes` (command units), each starting at `start_s` and rising over `rise_s`
/// (the thesis's step: one 30 Hz pulse update). Throws InvalidArgument for no or a zero amplitude.
std::vector<signal::Signal> step_excitations(const std::vector<double>& amplitudes, double start_s, double rise_s);

struct AxisCalibrationRun {
  std::string label;           ///< "step 10" or "chirp 2–40 Hz" (the signal and its amplitude)
  rig::BoardRecord record;
  rig::BoardRunOutcome outcome;
};

/// Runs every excitation on `board`, in order; stops after the first run that is not complete
/// (it is the last one returned). Throws what run_on_board throws.
std::vector<AxisCalibrationRun> record_calibration_runs(rig::SerialRig& board, const AxisCalibrationRequest& request);

/// Where a run's analysis window starts (request.from_s, or from its command as described there), s.
double analysis_start_s(const std::vector<double>& command, double sample_time_s, const AxisCalibrationRequest& request);

struct AxisCalibration {
  std::vector<advise::MeasuredSpectrum> spectra;  ///< one per run: the gyro rate in its window
  std::vector<double> window_start_s;             ///< per run
  advise::ModeEstimation estimation;
  advise::Recommendation recommendation;
};

/// The spectra, modes and ranked candidates of complete runs. Throws RuntimeError naming the
/// first incomplete run, advise::NoUsableResonance when no mode stands out of the noise, and
/// what estimate_modes and recommend throw.
AxisCalibration analyse_calibration(const std::vector<AxisCalibrationRun>& runs, const AxisCalibrationRequest& request,
                                    double sample_time_s);

/// The recommended candidate as a design to export (its shaper as applied, on the update grid
/// when options.update_grid_hz > 0). Throws RuntimeError when nothing was recommended (the
/// recommendation's reason and warning in the message).
exports::ShaperDesign recommended_design(const advise::Recommendation& recommendation,
                                         const advise::RecommendOptions& options);

}  // namespace clearshape::study
