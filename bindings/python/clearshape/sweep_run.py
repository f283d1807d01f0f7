"""One sweep point: the command run unshaped and shaped on the point's rig, and its metrics.

Metrics (docs/sweeps.md): Eq. 5.1 mean deviation MD unshaped and shaped — of the link angle
(deg) in position mode, of the link rate (deg/s) in speed mode, as the thesis's study (§5.1.2),
the steady state searched after the command starts — the improvement (%, thesis §5.1.2), the peak contact torque (N·m) of both runs, the
shaper's duration and the delay it adds to the response (s). The nominal rig (variation_scale
0) runs offline (clearshape.simulate: the true link motion); with variation the runs are
recorded from a SimRig that draws the truth's σs × variation_scale (the gyroscope's link rate,
integrated to the link angle in position mode; no contact torque is measured, so it is NaN).
"""
import math

import numpy as np

from . import _core

METRICS = ["md_unshaped", "md_shaped", "improvement_percent", "peak_torque_unshaped_n_m",
           "peak_torque_shaped_n_m", "shaper_duration_s", "delay_s"]


def _truth(p):
    t = _core.truth(p["truth"])
    if p["clearance_deg"] is not None:
        t.clearance_rad = p["clearance_deg"] * math.pi / 180.0
    if p["contact_stiffness"] is not None or p["contact_damping"] is not None:
        t.set_contact(p["mode"], stiffness=p["contact_stiffness"], damping=p["contact_damping"])
    if p["link_inertia_kg_m2"] is not None:
        t.link_inertia_kg_m2 = p["link_inertia_kg_m2"]
    v = t.variation
    t.variation = {k: x * p["variation_scale"] for k, x in v.items()}
    t.validate()
    return t


def _command(p, settings):
    params = {"amplitude": p["amplitude"], "start_s": p["start_s"]}
    if p["rise_s"] > 0:
        params["rise_s"] = p["rise_s"]
    _, u = _core.signal(p["signal"], rate_hz=settings["rate_hz"], duration_s=settings["duration_s"], **params)
    return u


def _run(p, settings, truth, command):
    """The Eq. 5.1 response (position: link angle deg; speed: link rate deg/s), the response the
    delay is measured on (the same), and the peak contact torque of one run."""
    ts = 1.0 / settings["rate_hz"]
    position = p["mode"] == "position"
    if p["variation_scale"] == 0:
        rig_cmd = command * math.pi / 180.0 if position else command
        r = _core.simulate(rig_cmd, ts, p["mode"], truth, duration_s=settings["duration_s"],
                           output_rate_hz=settings["rate_hz"], seed=p["seed"], sensor_noise=False)
        response = r["link_angle_rad" if position else "link_rate_rad_s"] * 180.0 / math.pi
        return response, float(np.max(np.abs(r["contact_torque_n_m"])))
    r = _core.simulate_rig(command, ts, p["mode"], truth, duration_s=settings["duration_s"], seed=p["seed"])
    rate = r["link_rate_deg_s"]
    if not position:
        return rate, math.nan
    # The link angle from the gyroscope, trapezoidal rule (as the study's link angle).
    angle = np.concatenate(([0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1])) * ts))
    return angle, math.nan


def evaluate(p, settings):
    """The metrics of point p (a dict from Sweep.points()); raises on a failed point."""
    ts = 1.0 / settings["rate_hz"]
    truth = _truth(p)
    command = _command(p, settings)
    shaper = _core.design(p["shaper"], frequency_hz=p["design_frequency_hz"] * (1.0 + p["frequency_error"]),
                          zeta=p["zeta"], vtol=p["vtol"])
    shaped = _core.shape(shaper, command, ts, extend=False)
    resp_u, torque_u = _run(p, settings, truth, command)
    resp_s, torque_s = _run(p, settings, truth, shaped)
    md_u = _core.mean_deviation(resp_u, ts, search_from_s=p["start_s"])["mean_deviation"]
    md_s = _core.mean_deviation(resp_s, ts, search_from_s=p["start_s"])["mean_deviation"]
    return {
        "md_unshaped": md_u,
        "md_shaped": md_s,
        "improvement_percent": _core.improvement_percent(md_u, md_s) if md_u > 0 else math.nan,
        "peak_torque_unshaped_n_m": torque_u,
        "peak_torque_shaped_n_m": torque_s,
        "shaper_duration_s": shaper.duration_s,
        "delay_s": _core.shaping_delay_s(resp_u, resp_s, ts),
    }


def run_batch(points, settings):
    """Evaluates a batch; a failed point is reported (status 'failed: <why>'), never dropped."""
    out = []
    for p in points:
        try:
            m = evaluate(p, settings)
            out.append({"index": p["index"], "status": "ok", **m})
        except Exception as e:  # noqa: BLE001 — one failed point must not lose the batch
            out.append({"index": p["index"], "status": f"failed: {type(e).__name__}: {e}",
                        **{k: math.nan for k in METRICS}})
    return out
