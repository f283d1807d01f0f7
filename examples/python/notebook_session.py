"""A notebook session with clearshape, cell by cell (run as a test: exits non-zero if a check fails).

The question: the thesis rig's link rings after a 20° position step; which shaper, designed
for the ringing we measure, removes it, and what does it cost in delay?
"""
import numpy as np

import clearshape as cs

# %% 1. The command: a 20° step at 0.1 s, 1 kHz, 3 s (deg in position mode).
t, step_deg = cs.signal("step", amplitude=20, start_s=0.1, duration_s=3.0)

# %% 2. Simulate the calibrated thesis rig without shaping (command in rad for the rig).
truth = cs.thesis_truth()
truth.clearance_rad = np.deg2rad(0.5)  # a worn joint: 0.5° of play
unshaped = cs.simulate(np.deg2rad(step_deg), 1e-3, "position", truth, duration_s=3.0)
link_rate_deg_s = np.rad2deg(unshaped["link_rate_rad_s"])

# %% 3. Identify the residual mode from the free ringing after the move (t > 0.5 s).
after = t > 0.5
mode = cs.modes(link_rate_deg_s[after], 1e-3)["modes"][0]
print(f"ringing: {mode['natural_frequency_hz']:.3f} Hz, zeta {mode['damping_ratio']:.4f}")

# %% 4. Design shapers for it and look at their robustness (V at ±20 % frequency error).
rows = []
for method in ["zv", "zvd", "ei"]:
    s = cs.design(method, frequency_hz=mode["natural_frequency_hz"], zeta=mode["damping_ratio"])
    r, v = cs.sensitivity(s, mode["natural_frequency_hz"], mode["damping_ratio"], 0.8, 1.2, 3)
    shaped_cmd = cs.shape(s, step_deg, 1e-3, extend=False)
    run = cs.simulate(np.deg2rad(shaped_cmd), 1e-3, "position", truth, duration_s=3.0)
    # Eq. 5.1 on the link angle (deg), steady state searched after the move starts (thesis §5.1.2).
    md_before = cs.mean_deviation(np.rad2deg(unshaped["link_angle_rad"]), 1e-3, search_from_s=0.1)["mean_deviation"]
    md_after = cs.mean_deviation(np.rad2deg(run["link_angle_rad"]), 1e-3, search_from_s=0.1)["mean_deviation"]
    rows.append((method, s.duration_s, v[0], v[2], md_before, md_after,
                 cs.improvement_percent(md_before, md_after)))

# %% 5. The table a notebook would show.
print(f"{'shaper':6} {'delay_s':>8} {'V(0.8)':>7} {'V(1.2)':>7} {'MD_unsh':>8} {'MD_sh':>8} {'impr_%':>7}")
for row in rows:
    print("{:6} {:8.4f} {:7.3f} {:7.3f} {:8.4f} {:8.4f} {:7.1f}".format(*row))

# Checks: every shaper reduces the Eq. 5.1 residual vibration; EI is the most robust at ±20 %.
assert all(row[6] > 0 for row in rows), rows
assert max(rows[2][2], rows[2][3]) < max(rows[0][2], rows[0][3])
