#!/usr/bin/python3
"""Simulated rig, 10 s runs: clearshape (CVODE BDF) vs SciPy solve_ivp on the same model.

The peer is an independent re-implementation of the plant equations (docs/design.md §2,
rig/truth.hpp): the rig's linear drive (its state-space realization read from the sidecar;
position mode: command deg -> motor angle; speed mode: V -> motor rate, integrated to the angle),
the link J·dω/dt = τ_contact − b_g·ω − b_j·dφ/dt with the torsional play |φ| <= β and the
thesis contact law F = max(K·δ^n + D·dδ/dt, 0) (Eq. 4.3, clamped), contact onset and
separation located as events (the law jumps there); the drive command interpolated linearly
(position mode: pulse count) or held piecewise constant with restarts where it changes
(speed mode: D/A). Parameters come from the run's JSON
sidecar; the drive command (after the 30 Hz pulse train or the 12-bit D/A) from its CSV.

Runs: the thesis position-mode step (20°, Table B.1) and a speed-mode step (2 V), step at
0.5 s, built-in truth, 1 kHz output — the work of bench_simulate. Prints, per run, the
clearshape and SciPy times, the speed ratio and the largest trajectory difference (motor and
link angle, link rate; relative to each signal's peak).

    /usr/bin/python3 bench/simulate_peer.py --build-dir build [--method BDF|Radau]
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

import numpy as np
from scipy import integrate

DEG = np.pi / 180.0
RUNS = [
    ("position", ["--mode", "position", "--signal", "step", "--amplitude", "20", "--start-s", "0.5"],
     "BM_SimulatePositionStep20deg"),
    ("speed", ["--mode", "speed", "--signal", "step", "--amplitude", "2", "--start-s", "0.5"],
     "BM_SimulateSpeedStep2V"),
]


class Plant:
    """Drive (the rig's linear realization) + link on a torsional play with the thesis law."""

    def __init__(self, mode, rig):
        drive = rig["drive"]  # x' = A x + B u, θ_m = c_angle·x (rad), ω_m = c_rate·x + d·u
        assert drive["delay_s"] == 0.0
        self.a = np.array(drive["a_matrix_cascade_realization"], dtype=float)
        self.b = np.array(drive["b_vector"], dtype=float)
        self.c_angle = np.array(drive["c_angle_rad"], dtype=float)
        self.c_rate = np.array(drive["c_rate_rad_s"], dtype=float)
        self.d_rate = float(drive["d_rate_rad_s"])
        self.mode = mode
        self.n = self.a.shape[0]
        link = rig["link"]
        self.J = link["inertia_kg_m2"]
        self.bg = link["ground_viscous_n_m_s_per_rad"]
        self.bj = rig["joint_friction"]["viscous_n_m_s_per_rad"]
        contact = rig["contact"]
        assert contact["model"] == "thesis"
        self.K = contact["stiffness_n_m_per_rad_pow_n"]
        self.ex = contact["exponent"]
        self.D = contact["damping_n_m_s_per_rad"]
        self.beta = 0.5 * rig["clearance_deg"] * DEG
        self.u = 0.0
        self.ramp = None  # position mode: (times, command) interpolated linearly
        self.contact = False
        self.side = 1.0

    def command(self, t):
        return self.u if self.ramp is None else np.interp(t, *self.ramp)

    def motor(self, y, t=0.0):  # motor angle and rate (rad, rad/s)
        x = y[: self.n]
        return self.c_angle @ x, self.c_rate @ x + self.d_rate * self.command(t)

    def force(self, phi, phi_rate):  # thesis Eq. 4.3, clamped at F >= 0
        if not self.contact:
            return 0.0, 0.0, 0.0
        s = self.side
        delta = max(s * phi - self.beta, 0.0)
        f = self.K * delta**self.ex + self.D * s * phi_rate
        if f <= 0.0:
            return 0.0, 0.0, 0.0
        return f, self.ex * self.K * delta ** (self.ex - 1.0), self.D

    def rhs(self, t, y):
        n = self.n
        dy = np.empty_like(y)
        dy[:n] = self.a @ y[:n] + self.b * self.command(t)
        _, wm = self.motor(y, t)
        phi, w = y[n], y[n + 1]
        phi_rate = w - wm
        f, _, _ = self.force(phi, phi_rate)
        dy[n] = phi_rate
        dy[n + 1] = (-self.side * f - self.bg * w - self.bj * phi_rate) / self.J
        return dy

    def jac(self, t, y):
        n = self.n
        jm = np.zeros((n + 2, n + 2))
        jm[:n, :n] = self.a
        _, wm = self.motor(y, t)
        phi, w = y[n], y[n + 1]
        _, f_delta, f_rate = self.force(phi, w - wm)
        dphi_rate = np.zeros(n + 2)  # ∂(ω − ω_m)/∂y
        dphi_rate[:n] = -self.c_rate
        dphi_rate[n + 1] = 1.0
        jm[n, :] = dphi_rate
        # τ = −s·F(δ, δ̇), δ = sφ − β, δ̇ = s·φ̇, s² = 1
        jm[n + 1, :] = (-(f_rate + self.bj) * dphi_rate) / self.J
        jm[n + 1, n] += -f_delta / self.J
        jm[n + 1, n + 1] += -self.bg / self.J
        return jm

    def gap(self, t, y):  # δ = |φ| − β (free) or s·φ − β (contact)
        phi = y[self.n]
        return (self.side * phi if self.contact else abs(phi)) - self.beta

    def tolerances(self, solver):  # as the rig's (plant/torsional_system.cpp tolerances())
        atol = np.full(self.n + 2, solver["angle_tolerance_rad"])
        angle_scale = np.max(np.abs(self.c_angle))
        rate_scale = np.max(np.abs(self.c_rate))
        for i in range(self.n):
            if self.mode == "position":
                atol[i] = solver["angle_tolerance_rad"] / angle_scale
            elif self.c_angle[i] == 0.0:  # speed drive: the states behind the rate output
                atol[i] = solver["rate_tolerance_rad_s"] / rate_scale
        atol[self.n + 1] = solver["rate_tolerance_rad_s"]
        return atol


def simulate(plant, times, command, method, rtol, atol):
    y = np.zeros(plant.n + 2)
    out = np.empty((times.size, plant.n + 2))
    out[0] = y
    if plant.mode == "position":  # pulse count interpolated linearly: no restarts
        plant.ramp = (times, command)
        bounds = [0, times.size - 1]
    else:  # D/A hold: restart where the command changes
        changes = np.nonzero(np.diff(command) != 0.0)[0] + 1
        bounds = [0, *changes.tolist(), times.size - 1]
    events = 0
    for k0, k1 in zip(bounds[:-1], bounds[1:]):
        if k1 <= k0:
            continue
        plant.u = command[k0]
        t0, t1 = times[k0], times[k1]
        while t0 < t1:
            def ev(t, yy):
                return plant.gap(t, yy)
            ev.terminal = True
            ev.direction = -1.0 if plant.contact else 1.0
            mask = (times > t0) & (times <= t1)
            sol = integrate.solve_ivp(plant.rhs, (t0, t1), y, method=method, t_eval=times[mask],
                                      events=ev, rtol=rtol, atol=atol, jac=plant.jac)
            if not sol.success:
                raise RuntimeError(sol.message)
            t_out = np.asarray(sol.t)
            if t_out.size:
                out[np.nonzero(mask)[0][: t_out.size]] = np.asarray(sol.y).T
            # t_eval always ends at t1, so a completed interval's last output is its end state.
            y = sol.y_events[0][0] if sol.status == 1 else np.asarray(sol.y)[:, -1]
            if sol.status == 1:
                events += 1
                t0 = sol.t_events[0][0]
                if plant.contact:
                    plant.contact = False
                else:
                    plant.contact = True
                    plant.side = 1.0 if y[plant.n] > 0 else -1.0
            else:
                t0 = t1
    return out, events


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default="build")
    ap.add_argument("--method", default="BDF", choices=["BDF", "Radau", "LSODA"])
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()
    cli = os.path.join(args.build_dir, "bin", "clearshape")
    bench = os.path.join(args.build_dir, "bench", "bench_simulate")
    for exe in (cli, bench):
        if not os.path.exists(exe):
            sys.exit(f"simulate_peer: {exe} not found; build it first (cmake --build {args.build_dir})")

    timing = json.loads(subprocess.run([bench, "--benchmark_format=json", "--benchmark_repetitions=3",
                                        "--benchmark_report_aggregates_only=true"],
                                       check=True, capture_output=True, text=True).stdout)
    ours = {}
    for b in timing["benchmarks"]:
        if b.get("aggregate_name") == "min" or (b.get("aggregate_name") == "mean" and b["run_name"] not in ours):
            scale = {"ms": 1e-3, "us": 1e-6, "ns": 1e-9, "s": 1.0}[b["time_unit"]]
            ours[b["run_name"]] = (b["real_time"] * scale, b["cpu_time"] * scale)

    print("wall time per 10 s run (first line) and CPU time (second line); RTF = simulated/wall time")
    print(f"{'run':<10}{'clearshape s':>14}{'SciPy s':>10}{'ratio':>9}{'rel. diff':>11}"
          f"{'events':>9}{'RTF':>9}")
    with tempfile.TemporaryDirectory() as tmp:
        for mode, flags, bench_name in RUNS:
            csv = os.path.join(tmp, f"{mode}.csv")
            subprocess.run([cli, "simulate", *flags, "--duration", "10", "--no-noise", "-o", csv],
                           check=True, capture_output=True)
            with open(os.path.join(tmp, f"{mode}.json")) as f:
                side = json.load(f)
            rig = side["configuration"]["rig"]
            data = np.genfromtxt(csv, delimiter=",", names=True)
            times = data["time_s"]
            command = data["drive_command_deg"] if mode == "position" else data["drive_command_v"]
            tol = rig["solver"]
            best = best_cpu = np.inf
            for _ in range(args.repeat):
                plant = Plant(mode, rig)
                atol = plant.tolerances(tol)
                start, start_cpu = time.perf_counter(), time.process_time()
                out, events = simulate(plant, times, command, args.method, tol["relative_tolerance"], atol)
                best = min(best, time.perf_counter() - start)
                best_cpu = min(best_cpu, time.process_time() - start_cpu)
            motor = out[:, : plant.n] @ plant.c_angle
            link_deg = (motor + out[:, plant.n]) / DEG
            link_rate = out[:, plant.n + 1] / DEG
            diffs = []
            for ours_col, peer in (("motor_deg", motor / DEG), ("link_deg", link_deg), ("link_deg_s", link_rate)):
                ref = data[ours_col]
                diffs.append(np.max(np.abs(ref - peer)) / max(np.max(np.abs(ref)), 1e-12))
            real_s, cpu_s = ours[bench_name]
            print(f"{mode:<10}{real_s:>14.4f}{best:>10.3f}{best / real_s:>8.0f}x{max(diffs):>11.2e}"
                  f"{events:>9d}{10.0 / real_s:>8.0f}x")
            print(f"{'':<10}CPU time: clearshape {cpu_s:.4f} s, SciPy {best_cpu:.3f} s, ratio "
                  f"{best_cpu / cpu_s:.0f}x, {10.0 / cpu_s:.0f}x real time; events clearshape "
                  f"{side['summary']['events']} / SciPy {events}; rel. diff motor/link/rate "
                  f"{diffs[0]:.1e}/{diffs[1]:.1e}/{diffs[2]:.1e}")


if __name__ == "__main__":
    main()
