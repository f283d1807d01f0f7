#pragma once
// Pieces of the files and JSON written about a commanded run, shared by `clearshape signal`,
// `simulate` and `rig run` so the three describe a signal and a shaper the same way.
#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "clearshape/shaping/shaper.hpp"
#include "clearshape/signal/signal.hpp"

namespace clearshape::cli {

/// `run.csv` → `run.json`: the sidecar that holds a run's configuration and summary.
std::filesystem::path sidecar_path(const std::string& output);

/// Every parameter of `signal` (signal::parameters_of), SI names, as a JSON object.
nlohmann::ordered_json signal_parameters_json(const signal::Signal& signal);

/// `{"method", "frequency_hz", "damping_ratio", "duration_s", "impulses": [{"time_s", "amplitude"}]}`
/// with the mode the shaper was designed for as given on the command line.
nlohmann::ordered_json shaper_json(const shaping::Shaper& shaper, double frequency_hz, double zeta);

}  // namespace clearshape::cli
