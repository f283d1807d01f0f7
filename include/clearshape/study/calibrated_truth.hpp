#pragma once
// Deprecated alias: the calibrated thesis rig is now the simulated rig's own built-in truth,
// rig::thesis_rig_truth() (rig/truth.hpp documents what was calibrated, to what, and the
// residuals; studies/sim-rig-truth.toml records the `clearshape calibrate-rig` output).
#include "clearshape/rig/truth.hpp"

namespace clearshape::study {

/// Same as rig::thesis_rig_truth().
inline rig::RigTruth calibrated_thesis_rig_truth() { return rig::thesis_rig_truth(); }

}  // namespace clearshape::study
