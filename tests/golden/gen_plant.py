#!/usr/bin/python3
"""Golden data for the plant module (run with /usr/bin/python3; SciPy is the independent
reference). Writes tests/golden/plant_drive_step.csv:

  thesis Eq. 4.2 process models G(s) = Kp (1 + Tz s) / ((1 + 2 Zeta Tw s + (Tw s)^2)(1 + Tp3 s))
  position mode: 10 deg command step at t = 0 -> motor angle (deg)
  speed mode:    1 command-unit step at t = 0 -> motor speed (deg/s) and its integral (deg)

sampled at 1 kHz over 0…1 s by scipy.signal.step (matrix exponential, exact for a step).
"""
import os

import numpy as np
from scipy import signal


def p3uz(kp, tz, zeta, tw, tp3, integrate=False):
    num = np.polymul([kp * tz, kp], [1.0])
    den = np.polymul([tw * tw, 2.0 * zeta * tw, 1.0], [tp3, 1.0])
    if integrate:
        den = np.polymul(den, [1.0, 0.0])
    return signal.lti(num, den)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    t = np.arange(0, 1001) * 1e-3
    pos = p3uz(0.9959, 0.0042, 0.9968, 0.0102, 0.0034)
    spd = p3uz(25.47, -0.0398, 0.2880, 0.0479, 0.0857)
    spd_angle = p3uz(25.47, -0.0398, 0.2880, 0.0479, 0.0857, integrate=True)
    _, y_pos = signal.step(pos, T=t)
    _, y_spd = signal.step(spd, T=t)
    _, y_ang = signal.step(spd_angle, T=t)
    data = np.column_stack([t, 10.0 * y_pos, y_spd, y_ang])
    np.savetxt(os.path.join(here, "plant_drive_step.csv"), data, delimiter=",",
               header="time_s,position_motor_deg,speed_motor_deg_s,speed_motor_deg",
               comments="", fmt="%.17g")


if __name__ == "__main__":
    main()
