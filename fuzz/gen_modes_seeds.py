#!/usr/bin/env python3
"""Writes the seed records of fuzz_modes (layout in fuzz/fuzz_modes.cpp) to fuzz/corpus/modes/."""
import math
import struct
from pathlib import Path

out = Path(__file__).resolve().parent / "corpus" / "modes"
out.mkdir(parents=True, exist_ok=True)


def int16(values):
    return b"".join(struct.pack("<h", max(-32768, min(32767, round(v * 1000)))) for v in values)


def free_decay(k, f_hz=14.0, zeta=0.05, amplitude=20.0, dt=1e-3):
    # x(t) = A e^(−ζωt) sin(ωd t): the free response of one mode (ωd = ω√(1−ζ²))
    w = 2 * math.pi * f_hz
    t = k * dt
    return amplitude * math.exp(-zeta * w * t) * math.sin(w * math.sqrt(1 - zeta * zeta) * t)


def step_second_order(k, wn=60.0, zeta=0.3, dt=1e-3):
    # unit-step response of ωn²/(s² + 2ζωn s + ωn²)
    t = k * dt
    wd = wn * math.sqrt(1 - zeta * zeta)
    return 1 - math.exp(-zeta * wn * t) * (math.cos(wd * t) + zeta / math.sqrt(1 - zeta * zeta) * math.sin(wd * t))


# selector 0: raw doubles, P1; 1: int16/1000, P1; 5: int16/1000, P2U
(out / "decay_raw.bin").write_bytes(bytes([0]) + struct.pack("<400d", *(free_decay(k, 8.0, 0.02, 1.0) for k in range(400))))
(out / "decay_int16.bin").write_bytes(bytes([1]) + int16(free_decay(k) for k in range(400)))
(out / "step_p2u_int16.bin").write_bytes(bytes([5]) + int16(step_second_order(k) for k in range(300)))
