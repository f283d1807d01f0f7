#pragma once
// `clearshape fit-clearance` as library calls (Python: clearshape.fit_clearance): the drive model
// of `clearshape identify --json`, link records (the command the drive received and the link
// gyro) into a study::ClearanceFitProblem, and the document of `fit-clearance --json` for a fit
// (study::fit_clearance, thesis §4.2) — which study/clearance_model_json.hpp reads back.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/lti/process_model.hpp"
#include "clearshape/rig/types.hpp"
#include "clearshape/study/model.hpp"

namespace clearshape::study {

/// The drive model in `clearshape identify --json` output (a fit, or cross-validation's best
/// model). Throws InputError naming the file for anything else.
lti::ProcessModel read_identified_drive(const std::filesystem::path& path);

/// Link records of one move, several repetitions averaged (as the study).
struct LinkRecordsRequest {
  std::vector<std::filesystem::path> files;  ///< CSV tables, same sample time and length
  std::string time_column;                    ///< empty: time_s, time or t
  std::string command_column;                 ///< empty: command_applied_deg|v, else command_deg|v
  std::string gyro_column = "link_rate_deg_s";
  double gyro_scale_deg_s = 1.0;              ///< deg/s per unit of the gyro column
  double window_s = 2.0;                      ///< compared from t = 0, s
  double envelope_window_s = 0.0;             ///< > 0: also the records' mean link-rate envelope
};

/// Fills `problem`'s drive command (the first record's), duration and measured link rate (the
/// mean of the records), and with an envelope window the mean envelope. Throws InputError
/// naming the file and column.
void read_link_records(const LinkRecordsRequest& request, rig::CommandMode mode, ClearanceFitProblem& problem);

/// Each record as its own run of the per-run fit (study::fit_clearance_runs; id = the file's
/// name): never averaged, because runs that start at different places in the play do not average
/// to any one run (docs/worn-coupling.md). Same columns and checks as read_link_records.
std::vector<ClearanceRunRecord> read_link_runs(const LinkRecordsRequest& request, rig::CommandMode mode);

/// The gyro low-pass bandwidths a fit tries when none is given: 0 (none) and the ITG-3205's
/// DLPF settings (256 … 5 Hz).
std::vector<double> gyro_low_pass_settings_hz();

/// The document `clearshape fit-clearance --json` prints: every parameter with its 1σ,
/// identifiability and bound, the Eq. 4.1 agreement (and at the start), warnings, and the rest of
/// the model (drive, link inertia, mode) so that the document alone describes it.
nlohmann::ordered_json fit_clearance_document(const ClearanceFitProblem& problem, const ClearanceFitResult& fit);

/// The per-run fit's check of n = 1 (results.json and `fit-clearance --per-run --json`): the
/// Gauss–Newton n with its 1σ, the χ²₁ statistic and whether n free fits significantly better.
nlohmann::ordered_json exponent_check_json(const ClearanceRunsFitResult& fit);

/// The same document for the per-run fit (`fit-clearance --per-run --json`): the shared
/// parameters with their 1σ (relative, run-clustered), each run's start place and flank damping,
/// `model_sigma` (with the flank damping's run spread) for the clearance-aware design, the n-free
/// check, and the rest of the model. clearance_model_json.hpp reads it back, sigma included.
nlohmann::ordered_json fit_clearance_runs_document(const ClearanceRunsFitProblem& problem,
                                                   const ClearanceRunsFitResult& fit);

}  // namespace clearshape::study
