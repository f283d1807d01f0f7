#pragma once
// Stages 1–3 (internal): repeatability (stage_consistency.cpp), drive identification
// (stage_identification.cpp) and the link's residual mode (stage_link_mode.cpp), each as
// plan → run → tabulate with the named results below between the steps; the runs are the
// unshaped runs of the run source (Context::unshaped_runs).
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "clearshape/ident/modes.hpp"
#include "clearshape/ident/process_fit.hpp"
#include "clearshape/ident/trust.hpp"
#include "clearshape/study/measures.hpp"
#include "context.hpp"

namespace clearshape::study::detail {

inline bool speed_mode(const Context& c) { return c.p.mode == rig::CommandMode::speed; }

/// The encoder signal of a run: angle (position mode) or speed through the §3.3 chain.
inline std::vector<double> encoder_signal(const Context& c, const Record& r) {
  if (speed_mode(c)) return motor_speed_deg_s(r, c.p.identification.speed_chain == "zero-phase");
  return r.motor_angle_deg;
}

inline std::string encoder_unit(const Context& c) { return speed_mode(c) ? "deg/s" : "deg"; }

/// Stage 1, one input: its repeated runs' encoder signals and their Eq. 4.1 errors.
struct ConsistencyInput {
  std::string name;
  const std::vector<Record>* runs = nullptr;
  std::vector<std::vector<double>> signals;  ///< run → encoder signal
  std::vector<double> errors;                ///< Eq. 4.1 per run (empty when it could not be computed)
  std::string note;                          ///< why not
};

/// Stage 2: the Eq. 4.2 fit of every identification input and their cross-validation (§4.2).
struct DriveFits {
  std::vector<ident::Experiment> experiments;  ///< input order of [identification] inputs
  std::vector<ident::ProcessEstimate> estimates;
  std::vector<std::vector<double>> fit;        ///< fit[i][j]: model i on record j, %
  std::vector<double> score;                   ///< mean cross-validation fit of model i, %
  std::vector<ident::TrustAssessment> trust;
  std::size_t best = 0;                        ///< the selected model
};

/// Stage 3: the link's free-response mode, run by run.
struct LinkModeRuns {
  std::vector<double> wn_rad_s, zeta, fit_percent;  ///< runs with a mode
  json per_run = json::array();                    ///< results.json sections.link_mode.runs
  /// The first run with a mode (its index) and its fit, for the figure.
  std::optional<std::pair<std::size_t, ident::ModeIdentification>> example;
};

}  // namespace clearshape::study::detail
