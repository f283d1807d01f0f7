"""The thesis's published numbers (Gündüzalp 2015), transcribed from the text.

Used by the synthetic fixture, and by the report only to fill in a thesis value that results.json
does not carry (the report then says so). Sources: Table 4.1 (p. 54), Table 4.2 (p. 57), Eq. 4.2 and
§4.2 (identified parameters), §4.2 end (Eq. 4.1 agreement of the clearance model), Table 5.1 (p. 78),
Table 5.2 (p. 89), Appendix B Tables B.1–B.6.
"""

TABLE_4_1 = {  # Eq. 4.1 error per trial, speed mode, columns: step, ramp, sine, PRBS
    "step": [0.0021, 0.0024, 0.0022, 0.0018, 0.0021, 0.0016, 0.0024, 0.0021, 0.0023, 0.0023],
    "ramp": [0.0018, 0.0015, 0.0022, 0.0019, 0.0016, 0.0023, 0.0015, 0.0023, 0.0018, 0.0014],
    "sine": [0.0012, 0.0013, 0.0013, 0.0009, 0.0007, 0.0006, 0.0007, 0.0010, 0.0008, 0.0011],
    "prbs": [0.0035, 0.0039, 0.0029, 0.0028, 0.0038, 0.0041, 0.0039, 0.0038, 0.0038, 0.0032],
}
TABLE_4_1_MEAN = {"step": 0.0021, "ramp": 0.0018, "sine": 0.0010, "prbs": 0.0035}

TABLE_4_2 = {  # Eq. 4.1 error per trial, position mode, columns: step, double step
    "step": [1.56e-4, 1.39e-4, 1.05e-4, 1.22e-4, 2e-4, 1.24e-4, 1.72e-4, 0.98e-4, 1.39e-4, 1.15e-4],
    "double_step": [0.0027, 0.0026, 0.0026, 0.0018, 0.0024, 0.0045, 0.0026, 0.0026, 0.0024, 0.0044],
}
TABLE_4_2_MEAN = {"step": 1.37e-4, "double_step": 0.0028}

EQ_4_2 = {  # identified drive models (Eq. 4.2): K, Tz [s], zeta, Tw [s], Tp3 [s]
    "speed": {"K": 25.47, "Tz_s": -0.0398, "zeta": 0.2880, "Tw_s": 0.0479, "Tp3_s": 0.0857},
    "position": {"K": 0.9959, "Tz_s": 0.0042, "zeta": 0.9968, "Tw_s": 0.0102, "Tp3_s": 0.0034},
}
CONTACT = {"speed": {"K": 5.0, "D": 350.0, "n": 1.5}, "position": {"K": 10000.0, "D": 300.0, "n": 1.5}}
CLEARANCE_AGREEMENT_EQ_4_1 = {"speed": 0.0067, "position": 0.0042}

TABLE_5_1 = {  # Eq. 5.1 mean deviation per trial, speed mode step (°/s)
    "unshaped": [0.303, 0.364, 0.385, 0.317, 0.409, 0.402, 0.431, 0.420, 0.463, 0.421],
    "zv": [0.172, 0.232, 0.195, 0.262, 0.156, 0.276, 0.181, 0.294, 0.244, 0.273],
    "zvd": [0.166, 0.264, 0.124, 0.240, 0.127, 0.254, 0.159, 0.268, 0.154, 0.241],
    "zvdd": [0.146, 0.220, 0.123, 0.259, 0.145, 0.231, 0.159, 0.250, 0.149, 0.230],
}
TABLE_5_1_MEAN = {"unshaped": 0.392, "zv": 0.229, "zvd": 0.198, "zvdd": 0.191}

# Position mode, Eq. 5.1 mean deviation per trial, without / with ZVDD (Table 5.2 = B.1 and B.5).
TABLE_B = {
    "B.1": {"input": "step 20°", "unshaped": [0.270, 0.307, 0.307, 0.308, 0.318, 0.334, 0.271, 0.302, 0.283, 0.332],
            "zvdd": [0.014, 0.007, 0.011, 0.015, 0.016, 0.014, 0.010, 0.013, 0.011, 0.018],
            "mean": {"unshaped": 0.303, "zvdd": 0.013}},
    "B.2": {"input": "step 10°", "unshaped": [0.138, 0.110, 0.148, 0.142, 0.151, 0.127, 0.163, 0.145, 0.115, 0.171],
            "zvdd": [0.014, 0.009, 0.008, 0.025, 0.021, 0.008, 0.013, 0.021, 0.025, 0.016],
            "mean": {"unshaped": 0.141, "zvdd": 0.016}},
    "B.3": {"input": "step 5°", "unshaped": [0.105, 0.081, 0.086, 0.080, 0.064, 0.088, 0.103, 0.078, 0.090, 0.078],
            "zvdd": [0.014, 0.038, 0.035, 0.040, 0.014, 0.024, 0.010, 0.033, 0.020, 0.026],
            "mean": {"unshaped": 0.085, "zvdd": 0.025}},
    "B.4": {"input": "step 56° (low jerk)",
            "unshaped": [0.242, 0.242, 0.242, 0.290, 0.226, 0.219, 0.295, 0.219, 0.236, 0.284],
            "zvdd": [0.055, 0.050, 0.050, 0.022, 0.029, 0.073, 0.046, 0.015, 0.066, 0.019],
            "mean": {"unshaped": 0.249, "zvdd": 0.042}},
    "B.5": {"input": "double step 16°",
            "unshaped": [0.273, 0.266, 0.288, 0.265, 0.288, 0.286, 0.277, 0.284, 0.263, 0.281],
            "zvdd": [0.027, 0.019, 0.018, 0.026, 0.020, 0.020, 0.025, 0.022, 0.023, 0.023],
            "mean": {"unshaped": 0.277, "zvdd": 0.022}},
}
TABLE_B_6 = {"B.1": 95.7, "B.2": 88.6, "B.3": 70.5, "B.4": 83.1, "B.5": 92.1}  # ZVDD improvement %
TABLE_5_1_IMPROVEMENT_ZVDD = 52.1  # % (§5.1.2)
