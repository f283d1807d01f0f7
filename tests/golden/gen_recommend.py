#!/usr/bin/python3
"""Golden data for `clearshape recommend` (advise/): recordings, their Welch spectra computed with
SciPy, and the shaper Klipper's calibrate_shaper would choose on those spectra.

Run with Debian's Python (it has NumPy and SciPy):   /usr/bin/python3 tests/golden/gen_recommend.py

Klipper's selection is implemented here independently from its published description
(docs/Measuring_Resonances.md and the shaper_calibrate description): for a shaper family, scan
the design frequency over a grid; at each, the "remaining vibrations" are the PSD weighted by the
shaper's vibration response, counting only what lies above 1/20 of the PSD's maximum, as a
fraction of the same sum without shaper, worst over the test damping ratios 0.075, 0.1, 0.15
(design damping 0.1); keep the least, then the lowest score smoothing * (v^1.5 + 0.2 v + 0.01)
among frequencies with v < 1.1 * least + 0.0005; across families a later one replaces the best
when its score is 20 % lower, or 5 % lower with 10 % less smoothing; a ZV pick gives way to the
first family with 10 % less vibration. The shapers are the classic closed forms (Singer & Seering
1990; Singhose 1994-1997, with Klipper's K-scaling for damping). Smoothing uses Klipper's
defaults (accel 5000, scv 5); it only orders shapers by length here.

Cases (seeded NumPy): one mode (14.955 Hz, zeta 0.13, rate response to white noise), two modes
(plus 38 Hz, zeta 0.04, one input driving both), a free decay of the one mode, a Klipper raw
accelerometer file with two axes' modes (42 Hz / 55 Hz); and a simulated clearshape run
(recommend_sim_run.csv, committed: `clearshape simulate` of a 20 deg position step). Writes:
  recommend_<case>.csv            the recording (time_s,gyro_deg_s or Klipper's raw format)
  recommend_<case>_psd.csv        SciPy's Welch PSD of it (clearshape's settings: Hann, segment
                                  the largest power of two <= N/4, 50 % overlap, nfft 4x, density),
                                  in Klipper's PSD format, bins <= 200 Hz, full precision
  recommend_klipper.json          per case: Welch settings, the scan grid, every family's fit
                                  (least and selected), Klipper's choice
"""
import json
import math
import os

import numpy as np
import scipy
from scipy import signal

HERE = os.path.dirname(os.path.abspath(__file__))

VIBRATION_REDUCTION = 20.0
DESIGN_DAMPING = 0.1
TEST_DAMPING = [0.075, 0.1, 0.15]
MAX_FREQ = 200.0
AUTOTUNE = ["zv", "mzv", "ei", "2hump_ei", "3hump_ei"]
ALL_FAMILIES = ["zv", "mzv", "zvd", "ei", "2hump_ei", "3hump_ei"]


# --- shapers: (amplitudes, times) for design frequency f and damping z ---------------------------
def shaper(name, f, z):
    v = 1.0 / VIBRATION_REDUCTION
    root = math.sqrt(1.0 - z * z)
    td = 1.0 / (f * root)             # damped period
    k = math.exp(-z * math.pi / root)  # decay over half a damped period
    if name == "zv":
        return [1.0, k], [0.0, 0.5 * td]
    if name == "zvd":
        return [1.0, 2.0 * k, k * k], [0.0, 0.5 * td, td]
    if name == "mzv":
        km = math.exp(-0.75 * z * math.pi / root)
        a1 = 1.0 - 1.0 / math.sqrt(2.0)
        return [a1, (math.sqrt(2.0) - 1.0) * km, a1 * km * km], [0.0, 0.375 * td, 0.75 * td]
    if name == "ei":
        a1 = 0.25 * (1.0 + v)
        return [a1, 0.5 * (1.0 - v) * k, a1 * k * k], [0.0, 0.5 * td, td]
    if name == "2hump_ei":
        v2 = v * v
        x = (v2 * (math.sqrt(1.0 - v2) + 1.0)) ** (1.0 / 3.0)
        a1 = (3.0 * x * x + 2.0 * x + 3.0 * v2) / (16.0 * x)
        a2 = (0.5 - a1) * k
        return [a1, a2, a2 * k, a1 * k ** 3], [0.0, 0.5 * td, td, 1.5 * td]
    if name == "3hump_ei":
        a1 = 0.0625 * (1.0 + 3.0 * v + 2.0 * math.sqrt(2.0 * (v + 1.0) * v))
        a2 = 0.25 * (1.0 - v) * k
        a3 = (0.5 * (1.0 + v) - 2.0 * a1) * k * k
        return [a1, a2, a3, a2 * k * k, a1 * k ** 4], [0.0, 0.5 * td, td, 1.5 * td, 2.0 * td]
    raise ValueError(name)


def response(sh, z, freqs):
    """Residual vibration V(f, z) of the impulses (Eq. 2.19), vectorised over freqs."""
    a, t = np.asarray(sh[0]), np.asarray(sh[1])
    w = 2.0 * np.pi * np.asarray(freqs)
    decay = a[None, :] * np.exp(-z * w[:, None] * (t[-1] - t[None, :]))
    wd = w * math.sqrt(1.0 - z * z)
    s = (decay * np.sin(wd[:, None] * t[None, :])).sum(axis=1)
    c = (decay * np.cos(wd[:, None] * t[None, :])).sum(axis=1)
    return np.hypot(s, c) / a.sum()


def remaining(sh, z, freqs, psd):
    thr = psd.max() / VIBRATION_REDUCTION
    v = response(sh, z, freqs)
    return np.maximum(v * psd - thr, 0.0).sum() / np.maximum(psd - thr, 0.0).sum()


def smoothing(sh, accel=5000.0, scv=5.0):
    a, t = sh
    total = sum(a)
    ts = sum(ai * ti for ai, ti in zip(a, t)) / total
    off90 = sum(ai * (scv + 0.5 * accel * (ti - ts)) * (ti - ts) for ai, ti in zip(a, t) if ti >= ts)
    off180 = sum(ai * 0.5 * accel * (ti - ts) ** 2 for ai, ti in zip(a, t))
    return max(off90 * math.sqrt(2.0) / total, off180 / total)


def fit_family(name, grid, freqs, psd):
    rows = []
    least = None
    for f in grid[::-1]:  # highest first: ties keep the higher frequency
        sh = shaper(name, f, DESIGN_DAMPING)
        v = max(remaining(sh, z, freqs, psd) for z in TEST_DAMPING)
        sm = smoothing(sh)
        row = {"frequency_hz": float(f), "vibrations": float(v), "smoothing": sm,
               "score": sm * (v ** 1.5 + 0.2 * v + 0.01)}
        rows.append(row)
        if least is None or v < least["vibrations"]:
            least = row
    selected = least
    for row in rows[::-1]:
        if row["vibrations"] < least["vibrations"] * 1.1 + 0.0005 and row["score"] < selected["score"]:
            selected = row
    return {"least": least, "selected": selected, "rows": rows}


def klipper_choice(fits):
    best = None
    for name in AUTOTUNE:
        s = dict(fits[name]["selected"], name=name)
        if (best is None or s["score"] * 1.2 < best["score"]
                or (s["score"] * 1.05 < best["score"] and s["smoothing"] * 1.1 < best["smoothing"])):
            best = s
        for row in fits[name]["rows"]:
            if row["vibrations"] < best["vibrations"] and row["smoothing"] < best["smoothing"]:
                best = dict(row, name=name)
    if best["name"] == "zv":
        for name in AUTOTUNE[1:]:
            s = fits[name]["selected"]
            if s["vibrations"] * 1.1 < best["vibrations"]:
                best = dict(s, name=name)
                break
    return best


# --- recordings -------------------------------------------------------------------------------
def rate_response(rng, n, fs, modes):
    """Sum of modes' rate responses s*g/(s^2 + 2 z w s + w^2) to white noise (ZOH-discretised)."""
    u = rng.standard_normal(n)
    y = np.zeros(n)
    for f, z, g in modes:
        w = 2.0 * math.pi * f
        b, a, _ = signal.cont2discrete(([g * w, 0.0], [1.0, 2.0 * z * w, w * w]), 1.0 / fs, method="zoh")
        y += signal.lfilter(np.ravel(b), a, u)
    return y


def welch_like_clearshape(x, fs):
    n = len(x)
    seg = min(max(1 << ((n // 4).bit_length() - 1), 64), n)
    f, p = signal.welch(x, fs, window="hann", nperseg=seg, noverlap=seg // 2, nfft=4 * seg, detrend="constant",
                        scaling="density", return_onesided=True)
    return f, p, {"segment": seg, "nfft": 4 * seg, "segments": (n - seg // 2) // (seg - seg // 2)}


def write_table(name, t, y, column="gyro_deg_s"):
    with open(os.path.join(HERE, name), "w") as fh:
        fh.write(f"time_s,{column}\n")
        for ti, yi in zip(t, y):
            fh.write(f"{ti:.6f},{yi:.9g}\n")


def write_psd(name, f, psds):
    keep = f <= MAX_FREQ
    with open(os.path.join(HERE, name), "w") as fh:
        fh.write("freq,psd_x,psd_y,psd_z,psd_xyz\n")
        for i in np.flatnonzero(keep):
            fh.write(",".join(f"{v:.15g}" for v in [f[i], *(p[i] for p in psds)]) + "\n")
    return f[keep], psds[3][keep]


def run_case(case, f, psd_xyz, grid_range, notes):
    lo, hi = grid_range
    grid = lo + 0.2 * np.arange(int(math.ceil((hi - lo) / 0.2 - 1e-9)))
    fits = {name: fit_family(name, grid, f, psd_xyz) for name in ALL_FAMILIES}
    choice = klipper_choice(fits)
    return {"case": case, "notes": notes, "grid_hz": [float(g) for g in grid],
            "families": {k: {"least": v["least"], "selected": v["selected"]} for k, v in fits.items()},
            "klipper_choice": {k: choice[k] for k in ("name", "frequency_hz", "vibrations", "smoothing", "score")}}


def add_gyro_case(out, case, t, y, fs, notes, truth):
    """A gyro-rate record as a case: recommend_<case>.csv, its PSD (x = xyz), Klipper's fits on 5-60 Hz."""
    write_table(f"recommend_{case}.csv", t, y)
    f, p, w = welch_like_clearshape(y, fs)
    fk, pk = write_psd(f"recommend_{case}_psd.csv", f, [p, 0 * p, 0 * p, p])
    c = run_case(case, fk, pk, (5.0, 60.0), notes)
    c["welch"] = w
    c["truth"] = truth
    out["cases"].append(c)


def main():
    out = {"generator": "tests/golden/gen_recommend.py", "numpy": np.__version__, "scipy": scipy.__version__,
           "design_damping": DESIGN_DAMPING, "test_damping_ratios": TEST_DAMPING,
           "vibration_reduction": VIBRATION_REDUCTION, "max_frequency_hz": MAX_FREQ, "cases": []}

    fs, n = 400.0, 6400
    t = np.arange(n) / fs
    # One mode: the thesis rig's link mode, rate response to white noise, 1 % sensor noise.
    rng = np.random.default_rng(20151)
    y = rate_response(rng, n, fs, [(14.955, 0.13, 100.0)])
    y += 0.01 * y.std() * rng.standard_normal(n)
    add_gyro_case(out, "one_mode", t, y, fs, "14.955 Hz, zeta 0.13, white-noise rate response",
                  [{"frequency_hz": 14.955, "damping_ratio": 0.13}])

    # Two modes: plus a lighter 38 Hz mode whose PSD peak is about half the first's.
    rng = np.random.default_rng(20152)
    y = rate_response(rng, n, fs, [(14.955, 0.13, 100.0), (38.0, 0.04, 27.0)])
    y += 0.01 * y.std() * rng.standard_normal(n)
    add_gyro_case(out, "two_modes", t, y, fs, "14.955 Hz zeta 0.13 and 38 Hz zeta 0.04",
                  [{"frequency_hz": 14.955, "damping_ratio": 0.13}, {"frequency_hz": 38.0, "damping_ratio": 0.04}])

    # Free decay of the one mode after a move (500 Hz, 3 s), 0.5 % noise.
    fs_d, n_d = 500.0, 1500
    td = np.arange(n_d) / fs_d
    wn, z = 2.0 * math.pi * 14.955, 0.13
    y = 80.0 * np.exp(-z * wn * td) * np.cos(wn * math.sqrt(1 - z * z) * td)
    y += 0.4 * np.random.default_rng(20153).standard_normal(n_d)
    add_gyro_case(out, "decay", td, y, fs_d, "free decay 14.955 Hz zeta 0.13", [{"frequency_hz": 14.955, "damping_ratio": 0.13}])

    # Klipper raw accelerometer file: x rings at 42 Hz, y at 55 Hz, z noise (1600 Hz, 2 s).
    fs_k, n_k = 1600.0, 3200
    tk = np.arange(n_k) / fs_k
    rng = np.random.default_rng(20154)
    ax = rate_response(rng, n_k, fs_k, [(42.0, 0.08, 2000.0)])
    ay = rate_response(rng, n_k, fs_k, [(55.0, 0.1, 1500.0)])
    az = 50.0 * rng.standard_normal(n_k)
    with open(os.path.join(HERE, "recommend_klipper_raw.csv"), "w") as fh:
        fh.write("#time,accel_x,accel_y,accel_z\n")
        for i in range(n_k):
            fh.write(f"{tk[i]:.6f},{ax[i]:.6f},{ay[i]:.6f},{az[i]:.6f}\n")
    # Klipper's own rate: N over the time span.
    tk_read = np.round(tk, 6)
    fs_read = n_k / (tk_read[-1] - tk_read[0])
    axr, ayr, azr = (np.round(a, 6) for a in (ax, ay, az))
    fx, px, w = welch_like_clearshape(axr, fs_read)
    _, py, _ = welch_like_clearshape(ayr, fs_read)
    _, pz, _ = welch_like_clearshape(azr, fs_read)
    fk, pk = write_psd("recommend_klipper_raw_psd.csv", fx, [px, py, pz, px + py + pz])
    c = run_case("klipper_raw", fk, pk, (20.0, 120.0), "Klipper raw: x 42 Hz zeta 0.08, y 55 Hz zeta 0.1, psd_xyz")
    c["welch"] = dict(w, sample_rate_hz=fs_read)
    c["truth"] = [{"frequency_hz": 42.0, "damping_ratio": 0.08}, {"frequency_hz": 55.0, "damping_ratio": 0.1}]
    out["cases"].append(c)

    # A simulated clearshape run (committed input, see its first line): the link's gyro after a
    # 20 deg position step on the built-in rig, from 0.2 s (the free decay and sensor noise).
    sim = np.genfromtxt(os.path.join(HERE, "recommend_sim_run.csv"), delimiter=",", names=True, skip_header=1)
    ts, ys = sim["time_s"], sim["gyro_deg_s"]
    fs_s = 1.0 / np.mean(np.diff(ts))
    f, p, w = welch_like_clearshape(ys, fs_s)
    fk, pk = write_psd("recommend_sim_run_psd.csv", f, [p, 0 * p, 0 * p, p])
    c = run_case("sim_run", fk, pk, (5.0, 60.0), "clearshape simulate: 20 deg position step, built-in rig, gyro")
    c["welch"] = w
    c["truth"] = [{"frequency_hz": math.sqrt(45.2 / 5e-3) / (2 * math.pi), "damping_ratio": 0.124 / (2 * math.sqrt(45.2 * 5e-3)),
                   "note": "linear contact stiffness K and damping D on the link inertia J (the rig's truth); the play softens it"}]
    out["cases"].append(c)

    with open(os.path.join(HERE, "recommend_klipper.json"), "w") as fh:
        json.dump(out, fh, indent=1)
        fh.write("\n")
    for c in out["cases"]:
        k = c["klipper_choice"]
        print(f"{c['case']}: Klipper picks {k['name']} at {k['frequency_hz']:.1f} Hz, vibrations {100 * k['vibrations']:.2f} %")


if __name__ == "__main__":
    main()
