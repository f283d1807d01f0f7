#pragma once
// Stage 5, the simulated tests (internal), as plan → run → tabulate: the plan designs each
// column's shaper (unshaped, then shaper@source), the runs simulate every input on the study's
// calibrated model, the tabulation writes the simulation table, its figures, the shapers'
// sensitivity curves (simulation_sensitivity.cpp) and results.json sections.shapers.
#include <optional>
#include <string>
#include <vector>

#include "clearshape/shaping/shaper.hpp"
#include "context.hpp"

namespace clearshape::study::detail {

/// One column of the simulation table: "none", or a shaper designed for a mode source.
struct SimulationColumn {
  std::string key;    ///< "none" or "<method>@<mode source>"
  std::string label;  ///< "unshaped" or "<method> (<mode source>)"
  std::optional<shaping::Shaper> shaper;  ///< nullopt: unshaped (column 0) or not designable
  std::string reason;                     ///< why it could not be designed
  std::string method() const { return key.substr(0, key.find('@')); }
  std::string mode_source() const { return key.substr(key.find('@') + 1); }
};

/// What the stage plans: its columns, the unshaped one first.
struct SimulationPlan {
  std::vector<SimulationColumn> columns;
};

/// What the runs produced, input by input (in the protocol's order).
struct SimulationRuns {
  std::vector<std::vector<double>> md;     ///< column → Eq. 5.1 per input (NaN: no steady state / no shaper)
  std::vector<std::vector<double>> delay;  ///< column → shaping delay per input, s
  std::vector<double> unshaped_time;       ///< time_s of the last unshaped run
  std::vector<std::vector<double>> unshaped_motor;  ///< input → motor angle (position) or rate (speed)
  std::vector<std::vector<double>> unshaped_link;   ///< input → link rate, deg/s
};

/// The shaper as designed for a mode source, before the drive's update grid (nullopt + reason).
std::optional<shaping::Shaper> design_off_grid(const Context& c, const std::string& method,
                                               const std::string& mode_source, std::string& reason);

/// The shaper sensitivity curves (Eq. 2.19) of every designed column: data/sensitivity.csv and
/// the figure "shaper-sensitivity".
void write_sensitivity_figure(Context& c, const SimulationPlan& plan);

}  // namespace clearshape::study::detail
