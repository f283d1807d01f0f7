#pragma once
// `clearshape recommend` as a library call (docs/recommend.md; Python: clearshape.recommend):
// recordings → spectra → modes → the ranked candidates (advise/recommend.hpp), then, given an
// identified nonlinear model, each candidate's predicted Eq. 5.1 MD for a move, the tie rule that
// uses it and the clearance-aware candidate (study/recommend_model.hpp,
// study/recommend_clearance_aware.hpp); and the JSON document `recommend --json` prints.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "clearshape/advise/mode_estimate.hpp"
#include "clearshape/advise/recommend.hpp"
#include "clearshape/advise/spectrum_input.hpp"
#include "clearshape/signal/generators.hpp"
#include "clearshape/signal/signal.hpp"
#include "clearshape/study/clearance_model_json.hpp"
#include "clearshape/study/recommend_clearance_aware.hpp"
#include "clearshape/study/recommend_model.hpp"

namespace clearshape::study {

/// The move a model's predictions are for, and how it is simulated.
struct MoveRequest {
  std::filesystem::path model;   ///< `fit-clearance --json` or a study's results.json
  std::string move_type = "step";  ///< the signal type (signal/parameters.hpp), for the output
  signal::Signal move = signal::Step{};
  double duration_s = 4.0;       ///< (0, 60] s
  double sample_time_s = 1e-3;   ///< 1 / the move's rate (10 Hz … 100 kHz)
  double initial_play_fraction = 0.0;  ///< φ(0)/β in [-1, 1]
  bool clearance_aware = false;  ///< also design the clearance-aware candidate (a step move only)
};

struct RecommendRequest {
  std::vector<advise::SpectrumRequest> data;  ///< one or more recordings (worst case over them)
  advise::ModeEstimateOptions modes;
  advise::RecommendOptions options;
  std::optional<MoveRequest> model;           ///< the predicted MDs; none: the spectrum alone
  std::string plot;                           ///< the figure's path, for the document (empty: none)
};

struct RecommendReport {
  std::vector<advise::MeasuredSpectrum> spectra;
  advise::ModeEstimation estimation;
  advise::Recommendation recommendation;
  std::optional<MovePrediction> prediction;               ///< with a model
  std::optional<ClearanceAwareCandidate> clearance_aware; ///< with a model and clearance_aware
};

/// The spectra, the modes and the ranked candidates (no model yet). Throws as load_spectrum,
/// estimate_modes and recommend do.
RecommendReport recommend_from_spectra(const RecommendRequest& request);

/// With `request.model`: reads the model, predicts every candidate's MD for the move, applies the
/// tie rule (apply_predicted_md) and designs the clearance-aware candidate when asked (on the
/// drive's update grid when options.update_grid_hz > 0). No change without a model.
void add_model_predictions(const RecommendRequest& request, RecommendReport& report);
/// The same with the model already read (read_clearance_model_json of request.model->model).
void add_model_predictions(const RecommendRequest& request, const IdentifiedClearanceModel& model, RecommendReport& report);

/// Both steps: what `clearshape recommend` computes.
RecommendReport recommend(const RecommendRequest& request);

/// The document `clearshape recommend --json` prints (schema_version, inputs, modes, scoring,
/// candidates, model, recommendation, reason, plot).
nlohmann::ordered_json recommend_document(const RecommendRequest& request, const RecommendReport& report);

/// The data of `recommend --plot`'s figure (python/plot_recommend.py; docs/recommend.md): each
/// spectrum with its unit, a Klipper file's axes and the PSD the pick leaves; every candidate's
/// worst-case V(f); the modes; the design offsets and the reason.
nlohmann::ordered_json recommend_plot_data(const RecommendReport& report);

/// A ready `clearshape shape` line for a candidate of `recommendation`.
std::string shape_command(const advise::CandidateResult& candidate, const advise::Recommendation& recommendation,
                          double grid_hz);

}  // namespace clearshape::study
