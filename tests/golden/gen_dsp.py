#!/usr/bin/python3
"""Golden data for the clearshape `dsp` module, computed with SciPy/NumPy.

Run with Debian's Python (it has SciPy):   /usr/bin/python3 tests/golden/gen_dsp.py
Writes tests/golden/dsp_*.json. The outputs are committed; CI never regenerates them.
Every input signal is generated here from a fixed seed and stored next to the expected
outputs, so the C++ tests read both from the same file.

Versions used for the committed files are recorded in each file ("scipy", "numpy").
"""
import json
import math
import os

import numpy as np
import scipy
from scipy import signal

HERE = os.path.dirname(os.path.abspath(__file__))


def dump(name, payload):
    payload = dict(payload)
    payload["generator"] = "tests/golden/gen_dsp.py"
    payload["scipy"] = scipy.__version__
    payload["numpy"] = np.__version__
    path = os.path.join(HERE, name)
    with open(path, "w") as f:
        json.dump(payload, f, separators=(",", ":"))  # floats are written with repr: round-trip exact
        f.write("\n")
    print(f"wrote {path} ({os.path.getsize(path)} bytes)")


def clist(values):
    return [[float(np.real(v)), float(np.imag(v))] for v in values]


# ---------------------------------------------------------------------------------------------
# Butterworth designs: butter(N, Wn, btype, fs=fs, output='sos') and output='zpk'.
THESIS_CUTOFF_HZ = 30.0 / (2.0 * math.pi)  # §3.3: 4th order, passband edge 30 rad/s; 1 kHz logging
BUTTER_CASES = [
    # (order, btype, cutoff(s) in Hz, fs in Hz)
    (4, "lowpass", THESIS_CUTOFF_HZ, 1000.0),
    (1, "lowpass", 10.0, 1000.0),
    (2, "lowpass", 100.0, 1000.0),
    (3, "lowpass", 45.0, 1000.0),
    (5, "lowpass", 250.0, 1000.0),  # fs/4: poles on the imaginary axis
    (7, "lowpass", 240.0, 500.0),   # close to Nyquist
    (16, "lowpass", 2.0, 1000.0),   # high order, low cutoff
    (4, "lowpass", 30.0 / (2.0 * math.pi), 100.0),
    (1, "highpass", 0.5, 100.0),
    (3, "highpass", 5.0, 200.0),
    (8, "highpass", 50.0, 1000.0),
    (16, "highpass", 400.0, 1000.0),
    (2, "bandpass", [5.0, 20.0], 1000.0),
    (3, "bandpass", [1.0, 100.0], 1000.0),
    (4, "bandpass", [50.0, 60.0], 1000.0),
    (5, "bandpass", [100.0, 400.0], 1000.0),
]


def gen_butter():
    cases = []
    for order, btype, wn, fs in BUTTER_CASES:
        sos = signal.butter(order, wn, btype=btype, fs=fs, output="sos")
        z, p, k = signal.butter(order, wn, btype=btype, fs=fs, output="zpk")
        w, h = signal.sosfreqz(sos, worN=[0.0, 1.0, 10.0, 100.0, 0.45 * fs], fs=fs)
        cases.append({
            "order": order,
            "btype": btype,
            "cutoff_hz": wn if isinstance(wn, list) else [wn],
            "fs_hz": fs,
            "sos": sos.tolist(),
            "zeros": clist(z),
            "poles": clist(p),
            "gain": float(k),
            "response_f_hz": [float(v) for v in w],
            "response": clist(h),
        })
    # zpk2sos on non-Butterworth systems (complex zeros, unequal counts).
    zpk_cases = []
    systems = [
        ([-1.0, -0.5 - 0.5j, -0.5 + 0.5j], [0.75, 0.8 + 0.1j, 0.8 - 0.1j], 1.0),
        signal.ellip(5, 1, 40, 0.3, output="zpk"),
        signal.cheby1(4, 0.5, [0.2, 0.4], btype="bandstop", output="zpk"),
        ([], [0.5, 0.2 + 0.3j, 0.2 - 0.3j, -0.4], 2.5),
        ([0.9], [0.5 + 0.5j, 0.5 - 0.5j], 0.3),
    ]
    for z, p, k in systems:
        sos = signal.zpk2sos(np.asarray(z, dtype=complex), np.asarray(p, dtype=complex), k)
        zpk_cases.append({"zeros": clist(z), "poles": clist(p), "gain": float(k), "sos": sos.tolist()})
    # Sweep: every order 1..16 for each band type, log-uniform seeded cutoffs.
    rng = np.random.default_rng(3000)
    sweep = []
    for btype in ("lowpass", "highpass", "bandpass"):
        for order in range(1, 17):
            fs = float(rng.choice([100.0, 500.0, 1000.0, 2000.0]))
            if btype == "bandpass":
                lo, hi = sorted(10 ** rng.uniform(-3, np.log10(0.49), size=2) * fs)
                wn = [float(lo), float(hi)]
            else:
                wn = float(10 ** rng.uniform(-3, np.log10(0.49)) * fs)
            sos = signal.butter(order, wn, btype=btype, fs=fs, output="sos")
            sweep.append({"order": order, "btype": btype, "cutoff_hz": wn if isinstance(wn, list) else [wn],
                          "fs_hz": fs, "sos": sos.tolist()})
    dump("dsp_butter.json", {"butter": cases, "zpk2sos": zpk_cases, "sweep": sweep})


# ---------------------------------------------------------------------------------------------
# Filtering: sosfilt, sosfilt_zi, sosfiltfilt on a fixed seeded signal.
def test_signal(n, fs, seed):
    rng = np.random.default_rng(seed)
    t = np.arange(n) / fs
    return (1.5 + np.sin(2 * np.pi * 3.0 * t) + 0.4 * np.sin(2 * np.pi * 80.0 * t)
            + 0.8 * (t > 0.7) + 0.2 * rng.standard_normal(n))


def gen_filter():
    fs = 1000.0
    x = test_signal(1000, fs, seed=20150601)
    designs = [
        (4, "lowpass", THESIS_CUTOFF_HZ),
        (3, "lowpass", 45.0),
        (5, "highpass", 20.0),
        (2, "bandpass", [5.0, 20.0]),
        (1, "lowpass", 10.0),
    ]
    cases = []
    for order, btype, wn in designs:
        sos = signal.butter(order, wn, btype=btype, fs=fs, output="sos")
        zi = signal.sosfilt_zi(sos)
        y_rest = signal.sosfilt(sos, x)
        y_zi, zf = signal.sosfilt(sos, x, zi=zi * x[0])
        entry = {
            "order": order,
            "btype": btype,
            "cutoff_hz": wn if isinstance(wn, list) else [wn],
            "sos": sos.tolist(),
            "zi": zi.tolist(),
            "sosfilt": y_rest.tolist(),
            "sosfilt_zi_x0": y_zi.tolist(),
            "zf": zf.tolist(),
            "sosfiltfilt_odd": signal.sosfiltfilt(sos, x).tolist(),
            "sosfiltfilt_even": signal.sosfiltfilt(sos, x, padtype="even").tolist(),
            "sosfiltfilt_constant": signal.sosfiltfilt(sos, x, padtype="constant").tolist(),
            "sosfiltfilt_none": signal.sosfiltfilt(sos, x, padtype=None).tolist(),
            "sosfiltfilt_odd_padlen50": signal.sosfiltfilt(sos, x, padlen=50).tolist(),
        }
        ntaps = 2 * len(sos) + 1 - min((sos[:, 2] == 0).sum(), (sos[:, 5] == 0).sum())
        entry["default_padlen"] = int(3 * ntaps)
        cases.append(entry)
    dump("dsp_filter.json", {"fs_hz": fs, "x": x.tolist(), "cases": cases})


# ---------------------------------------------------------------------------------------------
# Differentiation: np.gradient (edge_order 1 and 2), and the thesis encoder-speed chain.
def gen_differentiate():
    rng = np.random.default_rng(7)
    dt = 1e-3
    x = np.cumsum(rng.standard_normal(64)) * 0.01
    grad1 = np.gradient(x, dt)
    grad2 = np.gradient(x, dt, edge_order=2)

    # Thesis chain (§3.3, §4.1.1): encoder counts -> degrees -> d/dt -> Butterworth 4th order,
    # 30 rad/s, at 1 kHz. Counts of a 3000 p/r quadrature encoder decoded x4 (12000 counts/rev).
    counts_per_rev = 12000
    fs = 1000.0
    n = 3000
    t = np.arange(n) / fs
    angle_deg = 90.0 * (1.0 - np.cos(2 * np.pi * 0.5 * t)) + 2.0 * np.sin(2 * np.pi * 7.0 * t)
    angle_deg += 0.05 * rng.standard_normal(n)
    counts = np.floor(angle_deg / (360.0 / counts_per_rev)).astype(np.int64)
    deg = counts * (360.0 / counts_per_rev)
    sos = signal.butter(4, 30.0 / (2 * np.pi), fs=fs, output="sos")
    # Causal (real-time) chain: backward difference, at rest before the first sample, filter
    # starting from rest.
    d_back = np.concatenate(([0.0], np.diff(deg) * fs))
    causal = signal.sosfilt(sos, d_back)
    # Zero-phase (offline) chain: central difference (np.gradient, edge_order=1) + sosfiltfilt
    # with odd padding of 1 s (clearshape's kThesisZeroPhasePadS), capped at n - 1.
    zero_phase = signal.sosfiltfilt(sos, np.gradient(deg, 1.0 / fs), padlen=min(int(round(1.0 * fs)), n - 1))
    short = deg[:300]  # shorter than the pad: padlen = n - 1
    zero_phase_short = signal.sosfiltfilt(sos, np.gradient(short, 1.0 / fs), padlen=len(short) - 1)
    dump("dsp_differentiate.json", {
        "dt_s": dt, "x": x.tolist(), "gradient_edge1": grad1.tolist(),
        "gradient_edge2": grad2.tolist(),
        "encoder": {
            "counts_per_rev": counts_per_rev, "fs_hz": fs, "counts": counts.tolist(),
            "sos": sos.tolist(), "backward_difference_deg_s": d_back.tolist(),
            "causal_deg_s": causal.tolist(), "zero_phase_deg_s": zero_phase.tolist(),
            "zero_phase_first300_deg_s": zero_phase_short.tolist(),
        },
    })


# ---------------------------------------------------------------------------------------------
# Welch PSD and peak picking.
def gen_welch():
    fs = 1000.0
    n = 5000
    rng = np.random.default_rng(424242)
    t = np.arange(n) / fs
    x = (2.0 + 1.0 * np.sin(2 * np.pi * 12.5 * t) + 0.5 * np.sin(2 * np.pi * 47.0 * t + 0.3)
         + 0.25 * np.sin(2 * np.pi * 180.0 * t) + 0.3 * t + 0.5 * rng.standard_normal(n))
    cases = []
    settings = [
        dict(window="hann", nperseg=256),  # scipy's defaults (noverlap = 128, constant detrend)
        dict(window="hann", nperseg=500, noverlap=100, nfft=512, detrend="linear", scaling="spectrum"),
        dict(window="boxcar", nperseg=255, noverlap=0, detrend=False),
        dict(window="hann", nperseg=1001, nfft=1001),
        dict(window="hamming", nperseg=128, noverlap=96),
    ]
    for s in settings:
        f, p = signal.welch(x, fs=fs, **s)
        entry = {k: (v if v is not False else "none") for k, v in s.items()}
        entry["frequency_hz"] = f.tolist()
        entry["psd"] = p.tolist()
        cases.append(entry)
    # Peaks of the default-settings PSD.
    f, p = signal.welch(x, fs=fs, nperseg=256)
    peak_cases = []
    for opts in [dict(), dict(height=1e-3), dict(prominence=1e-3), dict(distance=5, height=1e-4),
                 dict(height=1e-4, prominence=1e-4, distance=3)]:
        idx, props = signal.find_peaks(p, **opts)
        prom = signal.peak_prominences(p, idx)[0]
        peak_cases.append({"options": opts, "indices": idx.tolist(), "prominences": prom.tolist()})
    # Plateaus and edges (scipy picks the middle of a plateau, rounding down).
    plateau = np.array([0, 1, 1, 0, 2, 2, 2, 1, 3, 3, 3, 3, 0, 5, 4, 4, 6], dtype=float)
    pidx, _ = signal.find_peaks(plateau)
    dump("dsp_welch.json", {
        "fs_hz": fs, "x": x.tolist(), "cases": cases, "peak_psd": p.tolist(), "peaks": peak_cases,
        "plateau": plateau.tolist(), "plateau_peaks": pidx.tolist(),
        "plateau_prominences": signal.peak_prominences(plateau, pidx)[0].tolist(),
    })


if __name__ == "__main__":
    gen_butter()
    gen_filter()
    gen_differentiate()
    gen_welch()
