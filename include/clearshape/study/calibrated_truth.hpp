#pragma once
// The simulated thesis rig's truth as calibrated by `clearshape calibrate-rig` (DESIGN.md §2;
// study/rig_calibration.hpp) — the values and their residuals are recorded in
// studies/sim-rig-truth.toml and docs/study-outputs.md. It starts from rig::thesis_rig_truth()
// and replaces what the calibration fitted:
//   speed drive     P3UZ whose response through the 30 rad/s chain is the thesis's Eq. 4.2
//   play, flank     total play 2β, thesis law F = K δ + D δ̇ (n = 1: a linear flank), both modes
//   gyroscope       rate-noise density (DLPF 42 Hz kept)
// The study's default rig (sim_rig_factory) is a SimRig built with it. Only the rig factory and
// the tests read it; the study runner never does.
#include "clearshape/rig/truth.hpp"

namespace clearshape::study {

rig::RigTruth calibrated_thesis_rig_truth();

}  // namespace clearshape::study
