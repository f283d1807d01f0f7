#pragma once
// `clearshape rig calibrate` (cmd_rig_calibrate.cpp), added to `clearshape rig` by cmd_rig.cpp.
#include <CLI/CLI.hpp>

namespace clearshape::cli {

/// Adds the `calibrate` subcommand to `rig_command`.
void add_rig_calibrate(CLI::App& rig_command);

}  // namespace clearshape::cli
