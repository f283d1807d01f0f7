#pragma once
// The figure of `clearshape recommend --plot`: the measured spectrum (a Klipper file's axes too,
// the PSD the pick leaves, the PSD's unit) and every candidate's remaining-vibration curve (as
// Klipper's calibrate_shaper draws them; data: study::recommend_plot_data), drawn by
// python/plot_recommend.py in the study's figure style (python/clearshape_plot), written
// atomically. The PNG has fixed metadata: the same inputs give the same bytes.
#include <filesystem>

#include "clearshape/study/recommend_report.hpp"

namespace clearshape::cli {

/// Throws InvalidArgument for a path that does not end in .png, RuntimeError when Python or
/// matplotlib fail (their message on stderr).
void write_recommend_plot(const std::filesystem::path& png, const study::RecommendReport& report);

/// The folder holding plot_recommend.py: $CLEARSHAPE_PYTHON_DIR, else the source tree's python/.
std::filesystem::path python_dir();

}  // namespace clearshape::cli
