#pragma once
// Reads an identified nonlinear model (drive + play + contact law) for clearance-aware design
// (`clearshape shape --method clearance-aware --model FILE`, `clearshape recommend --model FILE`;
// Python: clearshape.read_clearance_model) from either
//   - the JSON of `clearshape fit-clearance --json` (parameters, drive, link_inertia_kg_m2,
//     mode), or
//   - a study's results.json (sections.clearance, the identification's selected drive model,
//     sections.link_mode).
// The joint friction (Coulomb and viscous on the relative rate) is read where present
// (parameters.coulomb/viscous, sections.clearance.coulomb_n_m/viscous_n_m_s_per_rad); a file
// written before it was fitted reads as friction 0.
// Errors name the file and the missing key (InputError).
#include <filesystem>
#include <optional>

#include "clearshape/study/model.hpp"

namespace clearshape::study {

struct IdentifiedClearanceModel {
  ClearanceModel model;
  /// The link's identified residual mode, when the file has one (a study's link-mode stage).
  std::optional<double> link_frequency_hz;
  std::optional<double> link_damping_ratio;
  /// The fit's relative 1σ and the flank damping's run spread, when the file has them (a study's
  /// sections.clearance.model_sigma; a null σ reads as not finite): the design's uncertainty set.
  std::optional<ClearanceModelSigma> sigma;
};

IdentifiedClearanceModel read_clearance_model_json(const std::filesystem::path& path);

}  // namespace clearshape::study
