"""clearshape: input shaping for servo-driven joints with clearance.

The C++ library for Python: command signals and the drive's command paths, shaper design
(every method), residual vibration and sensitivity, offline and streaming shaping, the
simulated rig (also from a rig configuration file), identification, vibration modes, the
thesis's metrics (Eq. 4.1, Eq. 5.1) and shaper recommendation (on an identified clearance model).
NumPy arrays in and out; a bad parameter raises ValueError with the C++ message, a failure
while computing raises RuntimeError. Units are in the names (_s, _hz, _rad, _deg, _n_m).
Sweeps over rigs, commands and shapers: clearshape.sweep (docs/sweeps.md).
"""
from ._core import (  # noqa: F401
    __version__,
    RigTruth,
    Shaper,
    StreamingShaper,
    analyse_calibration,
    arm_mode_map,
    arm_modes,
    arm_move,
    arm_names,
    arm_text,
    consistency,
    design,
    export,
    export_formats,
    identify,
    fit_clearance,
    improvement_percent,
    insensitivity,
    load_rig_config,
    mean_deviation,
    modes,
    position_path,
    read_clearance_model,
    recommend,
    residual_vibration,
    rig_truth_from_toml,
    sensitivity,
    shape,
    shaper_methods,
    shaping_delay_s,
    signal,
    signal_parameters,
    signal_types,
    simulate,
    simulate_arm,
    simulate_rig,
    speed_path,
    study,
    thesis_truth,
    truth,
    truth_names,
    uncalibrated_truth,
)
